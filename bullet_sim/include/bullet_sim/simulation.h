// The simulator core's entry point: a world, the robots spawned into it, and the fixed step that runs
// every robot's plugins around the physics. ROS-free; time is a count of steps, never a clock.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/description/model_spec.h"
#include "bullet_sim/description/world_spec.h"
#include "bullet_sim/physics/physics_world.h"
#include "bullet_sim/physics/robot_body.h"
#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/plugins/registry.h"
#include "bullet_sim/sensing/ray_caster.h"

namespace bullet_sim {

/// Where a robot's root link goes: x, y, yaw, and optionally z, roll and pitch. Without z, the robot's lowest
/// collision point rests on the ground (z = 0): no falling from the sky, no sinking.
struct SpawnPose {
  double x = 0, y = 0, yaw = 0;          ///< [m], [m], [rad]
  std::optional<double> z;               ///< [m]
  double roll = 0, pitch = 0;            ///< [rad]
  std::map<std::string, double> joints;  ///< initial joint positions (spawn_model -J) [rad] or [m]; others 0
};

/// A spawn pose from what a service carries: a position [m] and an orientation quaternion. A number that is
/// not finite is an error naming it; a zero quaternion is taken for the identity, with a warning (as Gazebo
/// does); others are normalised. With `place_on_ground`, the position's z is ignored.
SpawnPose spawnPoseFrom(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation,
                        bool place_on_ground, Diagnostics& diagnostics);

class Simulation;

/// Makes the image source that a simulation's cameras render through; it may keep the simulation to draw.
using ImageSourceFactory = std::function<std::unique_ptr<ImageSource>(const Simulation& simulation)>;

struct SimulationOptions {
  PhysicsOptions physics;
  uint64_t seed = 0;  ///< seeds every sensor's noise; the same inputs and seed give a bit-identical run
  /// Builds the robots' plugins: the registry their models were parsed with. It must outlive the simulation.
  const PluginRegistry* plugins = &PluginRegistry::builtin();
  /// Gives cameras their images (scene/simulation_images.h over a renderer). Without it, cameras publish
  /// nothing: the node always gives one, and tools that draw no camera image need none.
  ImageSourceFactory images;
  /// A spawn pose farther than max_length from the origin is refused.
  Limits limits;
};

/// A spawned robot: its physics and its plugins.
class Robot {
 public:
  Robot(std::string name, std::unique_ptr<PhysicsRobot> body, const Eigen::Isometry3d& spawn_pose);
  ~Robot();

  const std::string& name() const { return name_; }
  PhysicsRobot& body() { return *body_; }
  const PhysicsRobot& body() const { return *body_; }
  const std::vector<std::unique_ptr<Plugin>>& plugins() const { return plugins_; }

  /// The plugins of type T (e.g. WheeledDrive, RayLidar).
  template <class T>
  std::vector<T*> pluginsOf() const {
    std::vector<T*> found;
    for (const auto& plugin : plugins_) {
      if (auto* typed = dynamic_cast<T*>(plugin.get())) found.push_back(typed);
    }
    return found;
  }

 private:
  friend class Simulation;
  std::string name_;
  std::unique_ptr<PhysicsRobot> body_;
  Eigen::Isometry3d spawn_pose_;
  JointPositions spawn_joints_;
  std::vector<std::unique_ptr<Plugin>> plugins_;
  std::vector<BodyId> ray_bodies_;  ///< per part; kNoBody for a part without collisions
};

class Simulation {
 public:
  explicit Simulation(WorldSpec world, SimulationOptions options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Adds a robot named `name`. Throws SpecError listing every problem (a name in use, a pose that is not
  /// finite or beyond the limits, a plugin naming a missing joint, ...), and then leaves the simulation as it
  /// was. Load messages go to `warnings`.
  /// A world saved with the robot in it is refused: a world model of the robot's name, or one with exactly
  /// the robot's collision shapes (matched one to one by type and size) whose bounding box overlaps the
  /// robot's at the spawn pose.
  Robot& spawn(const std::string& name, ModelSpec model, const SpawnPose& pose,
               std::vector<std::string>* warnings = nullptr);
  /// False when there is no robot of that name.
  bool remove(const std::string& name);
  Robot* robot(const std::string& name);
  const Robot* robot(const std::string& name) const;
  std::vector<std::string> robotNames() const;

  /// One step: plugins apply commands, physics advances by the step size, then plugins sense.
  void step();
  /// Robots back at their spawn poses and plugins as at spawn; time goes on.
  void resetWorld();
  /// resetWorld, and time restarts: the next step ends at t = step size.
  void resetSimulation();

  double time() const { return static_cast<double>(steps_) * options_.physics.step_size; }  ///< [s]
  uint64_t steps() const { return steps_; }
  double stepSize() const { return options_.physics.step_size; }
  const WorldSpec& world() const { return world_; }
  const Limits& limits() const { return options_.limits; }

 private:
  void refreshRays();
  /// Adds the robot's parts to the ray caster and builds its plugins; on an error, takes the parts back out.
  void equip(Robot& robot, Diagnostics& diagnostics);

  WorldSpec world_;
  SimulationOptions options_;
  std::unique_ptr<PhysicsWorld> physics_;
  RayCaster rays_;
  std::unique_ptr<ImageSource> images_;         ///< outlives the robots' cameras
  std::vector<std::unique_ptr<Robot>> robots_;  ///< destroyed before physics_, which they live in
  uint64_t steps_ = 0;
};

}  // namespace bullet_sim
