// What plugins see of a spawned robot: joints to read and drive, link frames to read.
// One implementation per wheel model (`contact`: a Bullet multibody; `raycast`: one body with ray wheels),
// and one for a model with no moving joints (one Bullet rigid body).
#pragma once

#include <Eigen/Geometry>

#include <limits>
#include <string>
#include <vector>

#include "bullet_sim/model/geometry.h"
#include "bullet_sim/model/model.h"

namespace bullet_sim {

/// The wheel-ground model of a robot whose drive plugin (or ros_control plugin, for its wheels) has no
/// <wheelModel> tag: "raycast" or "contact". A robot without wheels driven by either uses "contact".
constexpr const char* kDefaultWheelModel = "raycast";

/// Whether the model's base never moves: a static model, or a URDF whose root link is named `world`, which
/// Gazebo takes for the world itself, so that the joint to its child fixes (or turns) the model against the
/// world at its spawn pose.
inline bool hasFixedBase(const ModelSpec& model) { return model.is_static || model.root == "world"; }

/// Where a collision comes from: the link that declares it and its index among that link's collisions.
struct CollisionSource {
  std::string link;
  int index = 0;
  bool operator==(const CollisionSource& other) const { return link == other.link && index == other.index; }
};

/// A rigid part of the robot: links merged by fixed joints. Sensors see parts through their collisions.
struct RobotPart {
  std::string root_link;                ///< the link whose frame is the part's frame
  std::vector<std::string> links;       ///< every link merged into it
  std::vector<Collision> collisions;    ///< origins in the part's frame
  std::vector<CollisionSource> sources;  ///< per collision
};

/// A point where a robot's collision touches another collision, after a step.
struct ContactPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< [m] world, on the robot's collision
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   ///< unit, world: the way the contact pushes the robot
  double depth = 0;                                    ///< [m] of interpenetration
  Eigen::Vector3d force = Eigen::Vector3d::Zero();     ///< [N] on the robot's collision, world axes
};

/// What a robot's collision touches: one entry per other collision.
struct CollisionContact {
  std::string other;  ///< the other collision as Gazebo names it: model::link::collision
  std::vector<ContactPoint> points;
};

class RobotBody {
 public:
  virtual ~RobotBody() = default;

  virtual const ModelSpec& spec() const = 0;

  /// Index of a joint that moves (not fixed), or -1.
  virtual int jointIndex(const std::string& joint) const = 0;
  virtual double jointPosition(int joint) const = 0;  ///< [rad] or [m]
  virtual double jointVelocity(int joint) const = 0;  ///< [rad/s] or [m/s]
  virtual double jointEffort(int joint) const = 0;    ///< applied by the motor in the last step [N m] or [N]

  /// Drives a joint towards `velocity` with at most `max_effort` (Gazebo's joint "vel" + "fmax").
  virtual void setJointVelocity(int joint, double velocity, double max_effort) = 0;
  /// Holds a joint at `position` with at most `max_effort`.
  virtual void setJointPosition(int joint, double position, double max_effort) = 0;
  /// Pushes a joint with `effort` [N m] or [N] for the next step, on top of the motor a velocity or position
  /// command set, which stays; its URDF friction still acts (Gazebo's SetForce: gazebo_ros_control's effort
  /// joints push with it, and a drive plugin's velocity motor on the same joint keeps driving).
  virtual void setJointEffort(int joint, double effort) = 0;

  /// Sets the root link's world-frame velocity [m/s] and angular velocity [rad/s] (Gazebo's
  /// Model::SetLinearVel / SetAngularVel).
  virtual void setRootVelocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) = 0;
  /// Adds a force [N] and a torque [N m], in world axes, at the origin of `link`, for the coming step only.
  virtual void applyLinkWrench(const std::string& link, const Eigen::Vector3d& force,
                               const Eigen::Vector3d& torque) = 0;
  /// Whether applyJointEffort moves `joint`: not for a joint the wheel model moves kinematically (raycast:
  /// every joint but the wheels).
  virtual bool takesJointEffort(int joint) const = 0;
  /// Adds an effort [N m] or [N] to a joint for the coming step only (Gazebo's Joint::SetForce); nothing on a
  /// joint that takes none.
  virtual void applyJointEffort(int joint, double effort) = 0;

  /// World pose of any link, including links merged into a part by fixed joints.
  virtual Eigen::Isometry3d linkPose(const std::string& link) const = 0;
  /// World-frame velocity of a link's origin [m/s] and its angular velocity [rad/s].
  virtual Eigen::Vector3d linkLinearVelocity(const std::string& link) const = 0;
  virtual Eigen::Vector3d linkAngularVelocity(const std::string& link) const = 0;

  virtual const std::vector<RobotPart>& parts() const = 0;
  /// Index into parts() of the part holding `link`, or -1.
  virtual int partOf(const std::string& link) const = 0;
  virtual Eigen::Isometry3d partPose(int part) const = 0;

  /// What collision `source` touches after the last step; empty for a collision that never meets bodies (a
  /// `raycast` wheel, whose ray is its contact).
  virtual std::vector<CollisionContact> contacts(const CollisionSource& source) const = 0;
};

/// Joint positions by joint index (see RobotBody::jointIndex): [rad] or [m].
using JointPositions = std::vector<std::pair<int, double>>;

/// The longest physics substep at which a robot stays accurate, and what sets it.
struct SubstepLimit {
  double seconds = std::numeric_limits<double>::infinity();  ///< [s]
  std::string reason;  ///< e.g. "the raycast suspension's 140 rad/s"; "" when nothing limits it
};

/// The physics side of a robot: what the simulation calls around each step, on top of what plugins see.
class PhysicsRobot : public RobotBody {
 public:
  /// Runs before each physics substep of `substep` [s] (PhysicsWorld::step): applies again what acts through
  /// the whole step (plugins' forces and efforts, joint damping), since Bullet clears forces after each of
  /// its steps, and recomputes the wheel model's forces.
  virtual void beforeSubstep(double substep) = 0;
  /// Refreshes the cached link frames and forgets the step's forces; call after the world's step.
  virtual void afterStep() = 0;
  /// The longest substep its stiffest spring and lightest link allow: the world cuts its steps into substeps
  /// no longer than any of its robots'.
  virtual SubstepLimit substepLimit() const = 0;
  /// Puts the robot back at `root_pose`, at rest, with the joints in `joints` (index, position) there and
  /// every other joint at 0.
  virtual void reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) = 0;
  /// Moves the robot rigidly, its root link to `root_pose`; joint positions and all velocities stay.
  virtual void teleport(const Eigen::Isometry3d& root_pose) = 0;
  /// Puts the joints in `joints` (index, position) there, at rest; the root and the other joints stay.
  virtual void setJointPositions(const JointPositions& joints) = 0;
  /// The world's substep is now `step_size` [s]; the motors' limits are impulses per substep.
  virtual void setStepSize(double step_size) = 0;
  /// [J] what the wheel model's springs hold now (the `raycast` suspension's 1/2 k x^2); 0 for none.
  virtual double elasticEnergy() const { return 0; }
  /// Whether Bullet has put it to sleep (Gazebo's auto-disable): it costs nothing until something wakes it.
  virtual bool sleeping() const { return false; }
};

}  // namespace bullet_sim
