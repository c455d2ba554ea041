// Gazebo .world files (SDF) parsed with libsdformat into an immutable description of the static world.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/geometry.h"
#include "bullet_sim/common/limits.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/assets/package_resolver.h"

namespace bullet_sim {

/// A link of a world model: what the world API names and places (link_states, get_link_state).
struct WorldLinkSpec {
  std::string name;  ///< a nested model's links carry its name: "nested::link"
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< link frame in the model frame
  std::vector<std::string> collisions;                     ///< the names of its collisions
  // What simulating the model as a body needs (a model to spawn, readSdfModel):
  std::optional<InertialSpec> inertial;   ///< in the link frame
  bool gravity = true;                    ///< <gravity>
  bool self_collide = false;              ///< <self_collide>
  SurfaceSpec surface;                    ///< its first collision's <surface><friction><ode> mu and mu2
  std::vector<size_t> collision_indices;  ///< its collisions in the model's `collisions`
  std::vector<size_t> visual_indices;     ///< its visuals in the model's `visuals`
};

/// A joint of a model to spawn, in the model frame.
struct WorldJointSpec {
  std::string name;  ///< a nested model's joints, parents and children carry its name: "nested::joint"
  JointSpec::Type type = JointSpec::Type::kFixed;
  std::string parent;  ///< "world" for a joint to the world
  std::string child;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the joint frame in the model frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();         ///< unit, in the model frame
  double lower = -std::numeric_limits<double>::infinity();  ///< [rad] or [m]
  double upper = std::numeric_limits<double>::infinity();
  double effort = 0;    ///< [N m] or [N]; 0 = no limit given
  double velocity = 0;  ///< [rad/s] or [m/s]; 0 = no limit given
  double damping = 0;
  double friction = 0;
};

/// One <model> of the world: a static obstacle whose links are welded to the model frame, or a rigid body.
struct WorldModelSpec {
  std::string name;  ///< nested models are folded into their top-level model
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< model frame in the world frame
  /// What the file says. A world file's non-static model of one link is a rigid body; one of several links
  /// or with nested models is made static, with a warning.
  bool is_static = true;
  bool allow_auto_disable = true;  ///< <allow_auto_disable>
  std::vector<Collision> collisions;  ///< origins in the model frame (link pose and collision pose folded in)
  /// Origins in the model frame. A plane visual becomes a thin box of its <size>, top face on the plane,
  /// because a renderer needs a finite extent.
  std::vector<Visual> visuals;
  std::vector<WorldLinkSpec> links;  ///< nested models' links included
  /// A model to spawn keeps its joints and its plugins (sensors' included); a world file's models are rigid
  /// and run none, so these stay empty there.
  std::vector<WorldJointSpec> joints;
  std::vector<PluginElement> plugins;  ///< model plugins first, then sensors' in link order
};

/// A world's <spherical_coordinates>: where its origin lies on the WGS84 ellipsoid, and which way its x axis
/// points.
struct SphericalCoordinates {
  double latitude = 0;   ///< [deg]
  double longitude = 0;  ///< [deg]
  double elevation = 0;  ///< [m]
  double heading = 0;    ///< [rad] of the world's x axis, counter-clockwise from east (SDF's heading_deg)
};

/// A world's <physics><ode> and <max_contacts>, sdformat's defaults where the file gives none: what Gazebo's
/// get_physics_properties reports. Bullet solves the contacts, so they change nothing in a step.
struct OdeSettings {
  int iters = 50;
  int precon_iters = 0;
  double sor = 1.3;
  double cfm = 0;
  double erp = 0.2;
  double contact_max_correcting_vel = 100;  ///< [m/s]
  double contact_surface_layer = 0.001;     ///< [m]
  int max_contacts = 20;
};

struct WorldSpec {
  std::string source;  ///< file path (or label of the text), for messages
  std::string name;
  Eigen::Vector3d gravity{0, 0, -9.81};  ///< [m/s^2]
  double max_step_size = 0.001;          ///< [s] from <physics>
  double real_time_factor = 1.0;         ///< as the file says; real_time_update_rate is what paces the steps
  /// [steps per wall s] the pace: <real_time_update_rate> (0 = as fast as possible), as Gazebo paces its
  /// steps, or, in a <physics> without one, real_time_factor / max_step_size.
  double real_time_update_rate = 1000;
  OdeSettings ode;
  std::vector<WorldModelSpec> models;  ///< in file order, including the ground plane
  std::optional<SphericalCoordinates> spherical_coordinates;  ///< nullopt when the world gives none
};

struct WorldOptions {
  /// An <include> of a model that is on no folder of the model path, or a world's mesh that cannot be found,
  /// is an error. By default it is skipped (a mesh: the shapes using it), as Gazebo skips it, with one
  /// warning naming the model or mesh, the folders searched and how to add a model.
  bool strict_models = false;
  Limits limits;  ///< sizes, poses and counts beyond them are errors
};

/// Parses a .world file. Throws SpecError naming the file and listing all problems at once (sdformat errors,
/// unreadable meshes, unsupported geometry). Warnings (a non-static model made static, ignored elements such
/// as plugins, joints and sensors, unknown models, meshes that cannot be found) are appended to `warnings`
/// when it is not null.
///
/// libsdformat reads the file in a child process: it takes megabytes for each <model> it reads (home.world's
/// 16 furniture models: 90 MB), which this process never holds, and should it crash or hang on a file (within
/// limits.world_load_seconds), that is a load error naming the file, not the end of this process. Models that
/// repeat another's contents but for their name and pose are read once and copied.
///
/// <include> URIs: model://NAME is the SDF file that the model.config of folder NAME on Gazebo's model path
/// names (see GazeboPaths: GAZEBO_MODEL_PATH, package exports, the models bullet_sim ships such as
/// ground_plane and sun, ~/.gazebo/models); package:// and file:// go through `resolver`; anything else is an
/// error. Mesh URIs may be model://, package://, file:// or paths relative to the SDF file that holds them.
/// Sizes, poses and counts beyond options.limits are errors too.
WorldSpec loadWorld(const std::string& path, const PackageResolver& resolver,
                    std::vector<std::string>* warnings, const WorldOptions& options = {});

/// Like loadWorld, for SDF text. `source` names it in messages; relative mesh paths and includes are resolved
/// against the directory of `source`.
WorldSpec parseWorld(const std::string& sdf_text, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings, const WorldOptions& options = {});

/// loadWorld and parseWorld in this process, without a child: for the fuzzer.
WorldSpec loadWorldHere(const std::string& path, const PackageResolver& resolver,
                        std::vector<std::string>* warnings, const WorldOptions& options = {});
WorldSpec parseWorldHere(const std::string& sdf_text, const std::string& source,
                         const PackageResolver& resolver, std::vector<std::string>* warnings,
                         const WorldOptions& options = {});

/// A model's SDF as spawn_sdf_model receives it (<sdf><model>...</model></sdf>, also a model.sdf file's
/// text), read as a world's models are but keeping its joints, sensors and plugins: sdf_model.h makes it a
/// body.
/// `source` names it in messages. Throws SpecError as parseWorld does, also when the text holds no <model>.
/// libsdformat reads it in a child process, as loadWorld's worlds.
WorldModelSpec readSdfModel(const std::string& sdf_text, const std::string& source,
                            const PackageResolver& resolver, std::vector<std::string>* warnings,
                            const Limits& limits = Limits());
/// readSdfModel in this process, without a child: for the fuzzer.
WorldModelSpec readSdfModelHere(const std::string& sdf_text, const std::string& source,
                                const PackageResolver& resolver, std::vector<std::string>* warnings,
                                const Limits& limits = Limits());

/// The .world file a user means by `name`: an absolute path as it is; otherwise the name is looked up in the
/// folders of Gazebo's resource path (GAZEBO_RESOURCE_PATH and the packages' gazebo_media_path exports: so
/// "worlds/x.world" is <folder>/worlds/x.world), then in bullet_sim/worlds, then bullet_sim_bringup/worlds
/// (Gazebo-style "worlds/x.world" works there too), then relative to the current directory. nullopt, with
/// `error` saying where it looked, when none exists.
std::optional<std::string> findWorldFile(const std::string& name, const PackageResolver& resolver,
                                         std::string* error);

/// The world `name` (found by findWorldFile), as gzserver loads one: when it cannot be found or read, the
/// world `fallback` instead (unless it is ""), after a warning naming the file and listing its problems, as
/// gzserver falls back on worlds/empty.world. With options.strict_models a world that is found but refused
/// is an error: no fallback. `path`, when given, receives the file loaded. Throws std::runtime_error, listing
/// the problems, when neither loads.
WorldSpec loadWorldOrFallback(const std::string& name, const std::string& fallback,
                              const PackageResolver& resolver, std::vector<std::string>* warnings,
                              const WorldOptions& options = {}, std::string* path = nullptr);

}  // namespace bullet_sim
