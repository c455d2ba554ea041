// What bullet_sim's ROS-free command-line tools (render_model, bench) share: argument parsing helpers, the
// robot description from a URDF or an xacro file, and the world file a user means.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "bullet_sim/spec/package_resolver.h"

namespace bullet_sim {

/// A bad command line: the tool prints the message and its usage, and exits with status 2.
class UsageError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A failure to report on stderr, ending the tool with exit status 1.
class Failure : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A finite number that is the whole of `text`; UsageError naming `option` otherwise.
double parseNumber(const std::string& text, const std::string& option);

/// `text` cut at every `separator`; a trailing separator gives a trailing empty part.
std::vector<std::string> split(const std::string& text, char separator);

/// The URDF that `xacro file args...` prints. xacro's own messages go straight to our stderr.
std::string runXacro(const std::string& file, const std::vector<std::string>& args);

/// The whole of a URDF file.
std::string readUrdfFile(const std::string& path);

/// The world file for a --world option (see findWorldFile); bullet_sim's empty.world when `name` is empty.
std::string findWorld(const std::string& name, const PackageResolver& resolver);

}  // namespace bullet_sim
