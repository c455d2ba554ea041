// xacro's output kept on disk, so that a run of the same robot skips xacro's second of start-up.
#pragma once

#include <string>
#include <vector>

namespace bullet_sim {

/// Where cachedXacro keeps its files: $BULLET_SIM_CACHE_DIR, else $XDG_CACHE_HOME/bullet_sim/xacro, else
/// ~/.cache/bullet_sim/xacro.
std::string xacroCacheDir();

/// The URDF that `xacro file args...` prints (expandXacro), taken from `cache_dir` when an earlier expansion
/// had the same file, arguments and ROS_PACKAGE_PATH, and neither the file nor any file it includes (xacro
/// --deps) has been modified since. Entries are written atomically, so parallel runs may share the folder; a
/// folder that cannot be written only costs the cache. Throws std::runtime_error with xacro's message.
std::string cachedXacro(const std::string& file, const std::vector<std::string>& args,
                        const std::string& cache_dir = xacroCacheDir());

}  // namespace bullet_sim
