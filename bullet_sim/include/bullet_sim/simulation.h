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
#include "bullet_sim/entities.h"
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
  /// spawn_model -robot_namespace: when given (even "", the root), it replaces every plugin's <robotNamespace>.
  std::optional<std::string> robot_namespace;
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
  /// [steps per wall s] the pace whoever runs the simulation keeps; 0 = as fast as possible. The simulation
  /// only reports it (physicsProperties), and the world API may change it.
  double max_update_rate = 1000;
  uint64_t seed = 0;  ///< seeds every sensor's noise; the same inputs and seed give a bit-identical run
  /// Builds the robots' plugins: the registry their models were parsed with. It must outlive the simulation.
  const PluginRegistry* plugins = &PluginRegistry::builtin();
  /// The controller types ros_control loads by name. It must outlive the simulation.
  const ControllerRegistry* controllers = &ControllerRegistry::builtin();
  /// The parameters plugins read at run time (ros_control's): the parameter server in the node, a tree in
  /// tools and tests; nullptr for none. It must outlive the simulation.
  const ParameterSource* parameters = nullptr;
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

  /// One step: plugins apply commands, physics advances by the step size (in substeps, where a robot's
  /// stiffest spring or lightest link needs shorter ones), then plugins sense.
  void step();
  /// One line on the physics substep robot `name` runs at, and what sets it. Throws std::invalid_argument
  /// for an unknown robot.
  std::string substepNote(const std::string& name) const;
  /// Robots back at their spawn poses and plugins as at spawn; time goes on.
  void resetWorld();
  /// resetWorld, and time restarts: the next step ends at t = step size.
  void resetSimulation();

  double time() const { return timeAfter(steps_); }  ///< [s]
  uint64_t steps() const { return steps_; }
  double stepSize() const { return options_.physics.step_size; }
  const WorldSpec& world() const { return world_; }
  const Limits& limits() const { return options_.limits; }
  /// Where each of the world's models is now (parallel to world().models): the world API moves them.
  Eigen::Isometry3d worldModelPose(size_t model) const;
  /// The frame in which visual `visual` of world model `model` has its origin now: the model's frame, or,
  /// for a visual on a link that turned on a joint, that frame moved with the link. Its pose is this frame *
  /// its origin.
  Eigen::Isometry3d worldVisualFrame(size_t model, size_t visual) const;

  // Gazebo's world API (entities.h says how entities are named). A request that cannot be honoured throws
  // std::invalid_argument saying why, and changes nothing; a setter returns a note on what it left out, or
  // "".

  /// Any model or link, in the world frame; "", "world", "map" and "/map" are the world frame itself.
  EntityState entityState(const std::string& entity) const;
  /// Every model: the world's (static ones included), in file order, then the robots, in spawn order.
  std::vector<std::string> modelNames() const;
  /// Every model's world state under its name, in modelNames() order.
  std::vector<NamedState> modelStates() const;
  /// Every link of every model, scoped ("robot::base_link"): a robot's parts (links merged by fixed joints
  /// count as one, named by the first), and the links of the world's models.
  std::vector<NamedState> linkStates() const;
  /// A model's state: its frame (a robot's root link) relative to `reference`.
  EntityState modelState(const std::string& model, const std::string& reference = "") const;
  /// Teleports a model: a robot keeps its joint positions, and every link takes the twist (so the joints
  /// stop), as in Gazebo; a world model, static or not, moves with all its collisions.
  std::string setModelState(const std::string& model, const EntityState& state,
                            const std::string& reference = "");
  /// Any link, also one that a fixed joint merges into its parent.
  EntityState linkState(const std::string& link, const std::string& reference = "") const;
  /// Teleports the model of a link that is rigidly attached to its model frame (a robot's root part, or any
  /// link of a world model) so that the link gets `state`.
  std::string setLinkState(const std::string& link, const EntityState& state,
                           const std::string& reference = "");
  ModelProperties modelProperties(const std::string& model) const;
  LinkProperties linkProperties(const std::string& link) const;
  JointProperties jointProperties(const std::string& joint) const;
  /// Sets a robot's joints (others keep theirs) at rest; the root stays. Resets do not keep them.
  void setModelConfiguration(const std::string& model, const std::map<std::string, double>& positions);
  /// Drives a moving joint towards `velocity` [rad/s or m/s] with at most `max_effort` [N m or N] until
  /// something else drives it (Gazebo's joint "vel" and "fmax").
  void driveJoint(const std::string& joint, double velocity, double max_effort);
  /// Schedules a wrench; it is applied, at the link's centre of mass, before every step in its window.
  std::string applyBodyWrench(const BodyWrench& wrench);
  /// Drops every wrench scheduled on `body` (named as in applyBodyWrench).
  void clearBodyWrenches(const std::string& body);
  std::string applyJointEffort(const JointEffort& effort);
  void clearJointEfforts(const std::string& joint);
  PhysicsProperties physicsProperties() const;
  /// A new step size takes effect from the next step on; sim time goes on from where it is.
  void setPhysicsProperties(const PhysicsProperties& properties);

 private:
  struct Entity;  ///< a model, or one of its links (entities.cpp)
  /// A world model as it is now: where, and its ray-caster body; or, for a non-static one, its rigid body,
  /// which the world API treats as a robot without plugins.
  struct PlacedWorldModel {
    Eigen::Isometry3d pose;
    BodyId ray_body = kNoBody;
    std::unique_ptr<Robot> body;
    /// A body's: per link of its WorldModelSpec, its pose in the file, inverted, times the model's there
    /// (what makes the link's pose now the frame of its visuals' origins); per visual, its link.
    std::vector<Eigen::Isometry3d> link_to_model;
    std::vector<size_t> visual_link;
  };
  /// A scheduled wrench (world axes, about the link's centre of mass) or joint effort, between two sim times.
  struct ScheduledWrench {
    std::string robot, link;
    Eigen::Vector3d force, torque;
    double start, end;  ///< [s]; end is +infinity until cleared
  };
  struct ScheduledEffort {
    std::string robot;
    int joint;
    double effort, start, end;
  };

  double timeAfter(uint64_t steps) const {
    return time_base_ + static_cast<double>(steps - steps_at_base_) * options_.physics.step_size;
  }
  void refreshRays();
  /// Cuts the step into substeps no longer than any moving model's SubstepLimit, and tells them.
  void fitSubsteps();
  /// The non-static world model `model` as a body at its pose in the file, into `placed`.
  void makeWorldBody(const WorldModelSpec& model, PlacedWorldModel& placed);
  /// The robots and the world's bodies: what steps.
  std::vector<Robot*> movingModels();
  /// Adds the parts of a robot or of a world's body to the ray caster (not yet committed).
  void addRayBodies(Robot& robot);
  /// Adds the robot's parts to the ray caster and builds its plugins; on an error, takes the parts back out.
  void equip(Robot& robot, const std::optional<std::string>& robot_namespace, Diagnostics& diagnostics);
  /// Applies the scheduled wrenches and efforts whose window holds the step that starts now; drops the ended.
  void applyScheduled();
  /// Drops every wrench and effort scheduled on robot `robot`.
  void clearScheduled(const std::string& robot);
  void moveWorldModel(size_t model, const Eigen::Isometry3d& pose);
  /// Throws std::invalid_argument naming `what` and the names there are.
  Entity findEntity(const std::string& name, const std::string& what) const;
  Entity findModel(const std::string& name) const;
  Entity findLink(const std::string& name) const;
  /// The robot and link a wrench acts on: a link, or a robot meaning its root link.
  std::pair<Robot*, std::string> findBody(const std::string& name) const;
  /// The robot and joint index of a moving joint ("robot::joint" or a bare name).
  std::pair<Robot*, int> findJoint(const std::string& name) const;
  EntityState worldState(const Entity& entity) const;
  std::string setWorldState(const Entity& model, const EntityState& state);

  WorldSpec world_;
  SimulationOptions options_;
  std::unique_ptr<PhysicsWorld> physics_;
  RayCaster rays_;
  std::unique_ptr<ImageSource> images_;         ///< outlives the robots' cameras
  std::vector<std::unique_ptr<Robot>> robots_;  ///< destroyed before physics_, which they live in
  std::vector<PlacedWorldModel> world_models_;  ///< parallel to world_.models; destroyed before physics_
  std::vector<ScheduledWrench> wrenches_;
  std::vector<ScheduledEffort> efforts_;
  uint64_t steps_ = 0;
  double time_base_ = 0;        ///< [s] at steps_at_base_: the step size may change
  uint64_t steps_at_base_ = 0;
};

}  // namespace bullet_sim
