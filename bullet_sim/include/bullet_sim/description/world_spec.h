// Gazebo .world files (SDF) parsed with libsdformat into an immutable description of the static world.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/description/diagnostics.h"
#include "bullet_sim/description/geometry.h"
#include "bullet_sim/description/limits.h"
#include "bullet_sim/description/package_resolver.h"

namespace bullet_sim {

/// One <model> of the world. World models are static obstacles: every link is welded to the model frame.
struct WorldModelSpec {
  std::string name;  ///< nested models are folded into their top-level model
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< model frame in the world frame
  /// What the file says. A non-static model is still simulated as static (with a warning).
  bool is_static = true;
  std::vector<Collision> collisions;  ///< origins in the model frame (link pose and collision pose folded in)
  /// Origins in the model frame. A plane visual becomes a thin box of its <size>, top face on the plane,
  /// because a renderer needs a finite extent.
  std::vector<Visual> visuals;
};

struct WorldSpec {
  std::string source;  ///< file path (or label of the text), for messages
  std::string name;
  Eigen::Vector3d gravity{0, 0, -9.81};  ///< [m/s^2]
  double max_step_size = 0.001;          ///< [s] from <physics>
  double real_time_factor = 1.0;
  std::vector<WorldModelSpec> models;  ///< in file order, including the ground plane
};

/// Parses a .world file. Throws SpecError naming the file and listing all problems at once (sdformat errors,
/// missing meshes, unsupported geometry). Warnings (a non-static model made static, ignored elements such as
/// plugins, joints and sensors) are appended to `warnings` when it is not null.
///
/// libsdformat reads the file in a child process: it takes megabytes for each <model> it reads (home.world's
/// 16 furniture models: 90 MB), which this process never holds, and should it crash or hang on a file (within
/// limits.world_load_seconds), that is a load error naming the file, not the end of this process.
///
/// <include> URIs: model://ground_plane and model://sun are built in (the sun is a light, so it adds no
/// model); package:// and file:// go through `resolver`; anything else is an error. Mesh URIs may be
/// package://, file:// or paths relative to the SDF file that holds them.
/// Sizes, poses and counts beyond `limits` are errors too.
WorldSpec loadWorld(const std::string& path, const PackageResolver& resolver,
                    std::vector<std::string>* warnings, const Limits& limits = Limits());

/// Like loadWorld, for SDF text. `source` names it in messages; relative mesh paths and includes are resolved
/// against the directory of `source`.
WorldSpec parseWorld(const std::string& sdf_text, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings, const Limits& limits = Limits());

/// loadWorld and parseWorld in this process, without a child: for the fuzzer.
WorldSpec loadWorldHere(const std::string& path, const PackageResolver& resolver,
                        std::vector<std::string>* warnings, const Limits& limits = Limits());
WorldSpec parseWorldHere(const std::string& sdf_text, const std::string& source,
                         const PackageResolver& resolver, std::vector<std::string>* warnings,
                         const Limits& limits = Limits());

/// The .world file a user means by `name`: an absolute path as it is; otherwise the name is looked up in
/// bullet_sim/worlds, then bullet_sim_bringup/worlds (Gazebo-style "worlds/x.world" works too), then relative
/// to the current directory. nullopt, with `error` saying where it looked, when none exists.
std::optional<std::string> findWorldFile(const std::string& name, const PackageResolver& resolver,
                                         std::string* error);

}  // namespace bullet_sim
