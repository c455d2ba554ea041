// Gazebo's world API (gazebo_ros's api plugin) over a simulation: entity states in reference frames,
// teleports, properties, joint configurations and motors, scheduled wrenches and efforts, physics
// properties. ROS-free; the ROS layer only translates gazebo_msgs (ros/gazebo_services.h).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bullet_sim/simulation/entities.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

/// Entities are named as entities.h says. A request that cannot be honoured throws std::invalid_argument
/// saying why, and changes nothing; a setter returns a note on what it left out, or "".
/// It applies its scheduled wrenches and efforts at every step of `simulation`, which must outlive it.
class WorldApi : private StepHooks {
 public:
  /// `max_update_rate` [steps per wall s]: the pace whoever runs the simulation keeps (0 = as fast as
  /// possible). The world API only reports it, and set_physics_properties changes it.
  explicit WorldApi(Simulation& simulation, double max_update_rate = 1000);

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
  /// Sets a robot's joints (others keep theirs) at rest; the root stays. Resets do not keep them. As Gazebo,
  /// a name that is no moving joint of the robot is skipped; the note returned names those skipped ("" if
  /// none). Its plugins are told (Plugin::jointsPlaced), and what they warn of joins the note.
  std::string setModelConfiguration(const std::string& model, const std::map<std::string, double>& positions);
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
  /// A model (a robot, or the world's model of an index), or one of its links.
  struct Entity {
    Robot* robot = nullptr;  ///< the model is a robot, or a world model's body,
    int world_model = -1;    ///< or the world's model of this index
    std::string link;        ///< "" for the model itself
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

  /// Applies the scheduled wrenches and efforts whose window holds the step that starts now; drops the ended.
  void beforeStep() override;
  /// Drops every wrench and effort scheduled on robot `name`.
  void robotRemoved(const std::string& name) override;

  /// Throws std::invalid_argument naming `what` and the names there are.
  Entity findEntity(const std::string& name, const std::string& what) const;
  Entity findModel(const std::string& name) const;
  Entity findLink(const std::string& name) const;
  /// The robot and link a wrench acts on: a link, or a robot meaning its root link.
  std::pair<Robot*, std::string> findBody(const std::string& name) const;
  /// The robot and joint index of a moving joint ("robot::joint" or a bare name).
  std::pair<Robot*, int> findJoint(const std::string& name) const;
  /// The world's bodies, then the robots, as modelNames() lists them.
  std::vector<Robot*> modelsWithJoints() const;
  EntityState worldState(const Entity& entity) const;
  std::string setWorldState(const Entity& model, const EntityState& state);

  Simulation& simulation_;
  double max_update_rate_;
  std::vector<ScheduledWrench> wrenches_;
  std::vector<ScheduledEffort> efforts_;
};

}  // namespace bullet_sim
