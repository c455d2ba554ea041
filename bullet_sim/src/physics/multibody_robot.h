// The `contact` wheel model: the robot as one Bullet multibody (Featherstone), whose wheels touch the ground
// through their collision shapes and are driven by velocity motors limited by the plugin's torque.
#pragma once

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "bullet_sim/physics/robot_body.h"
#include "physics/contacts.h"

class btCollisionObject;
class btMultiBody;
class btMultiBodyDynamicsWorld;
class btMultiBodyJointMotor;
class btMultiBodyLinkCollider;
class btMultiBodyConstraint;
class btMultiBodyGearConstraint;
class btCollisionShape;

namespace bullet_sim {

class BulletShapes;
class SelfCollisionRule;

/// Bullet collision filter groups: the robots' parts test only static geometry and other robots.
enum CollisionGroup : int { kStaticGroup = 1, kRobotGroup = 2 };

class MultiBodyRobot : public PhysicsRobot {
 public:
  /// Builds the robot with its root link at `root_pose` and adds it to `world`. Throws SpecError when the
  /// model cannot be simulated (a part without mass); `world` is untouched then.
  /// `name` is the robot's, as contacts name its collisions (model::link::collision).
  MultiBodyRobot(ModelSpec spec, std::string name, btMultiBodyDynamicsWorld& world,
                 const Eigen::Isometry3d& root_pose);
  ~MultiBodyRobot() override;
  MultiBodyRobot(const MultiBodyRobot&) = delete;
  MultiBodyRobot& operator=(const MultiBodyRobot&) = delete;

  void beforeSubstep(double substep) override;
  void afterStep() override;
  SubstepLimit substepLimit() const override;
  void reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) override;
  void teleport(const Eigen::Isometry3d& root_pose) override;
  void setJointPositions(const JointPositions& joints) override;
  void setStepSize(double step_size) override;
  bool sleeping() const override;

  const ModelSpec& spec() const override { return spec_; }
  int jointIndex(const std::string& joint) const override;
  double jointPosition(int joint) const override;
  double jointVelocity(int joint) const override;
  double jointEffort(int joint) const override;
  void setJointVelocity(int joint, double velocity, double max_effort) override;
  void setJointPosition(int joint, double position, double max_effort) override;
  void setJointEffort(int joint, double effort) override;
  void setRootVelocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) override;
  void applyLinkWrench(const std::string& link, const Eigen::Vector3d& force,
                       const Eigen::Vector3d& torque) override;
  bool takesJointEffort(int joint) const override;
  void applyJointEffort(int joint, double effort) override;
  Eigen::Isometry3d linkPose(const std::string& link) const override;
  Eigen::Vector3d linkLinearVelocity(const std::string& link) const override;
  Eigen::Vector3d linkAngularVelocity(const std::string& link) const override;
  const std::vector<RobotPart>& parts() const override { return parts_; }
  int partOf(const std::string& link) const override;
  Eigen::Isometry3d partPose(int part) const override;
  std::vector<CollisionContact> contacts(const CollisionSource& source) const override;

 private:
  struct PartFrames {
    /// Bullet's frame: com, principal axes
    Eigen::Isometry3d part_to_bullet = Eigen::Isometry3d::Identity();
    std::unordered_map<std::string, Eigen::Isometry3d> link_in_part;
    double mass = 0;                                              ///< [kg] of every link in the part
    Eigen::Vector3d principal_inertia = Eigen::Vector3d::Zero();  ///< [kg m^2] about Bullet's frame axes
  };
  struct Scratch;  ///< Bullet's work arrays, kept to avoid allocating per step
  struct Joint {
    const JointSpec* spec;
    int bullet_link;                         ///< index of the child part's Bullet link
    double inertia = 0;  ///< [kg m^2] of the child part about the axis ([kg]: its mass, prismatic)
    btMultiBodyJointMotor* motor = nullptr;  ///< created on first command; owned by `constraints_`
    /// to the joint it mimics, if any; owned by `constraints_`
    btMultiBodyGearConstraint* coupling = nullptr;
    double pending_effort = 0;               ///< [N m] or [N] pushed with in the coming step (setJointEffort)
    double applied_effort = 0;               ///< and in the last one
    double step_effort = 0;  ///< [N m] or [N] pushed with through the coming step, applyJointEffort's too
  };

  void buildParts();
  void buildMultiBody(const Eigen::Isometry3d& root_pose);
  /// Joins part `k` to its parent part with its joint (revolute or prismatic).
  void setupJoint(int k);
  /// [kg m^2] part k's moment about its joint's axis, or [kg] its mass for a prismatic joint: what the
  /// joint's damping slows.
  double jointInertia(int k) const;
  /// Gives part `k` its collision shape, friction and contact stiffness.
  void addCollider(int k);
  btMultiBodyJointMotor* motorFor(Joint& joint);
  /// Wakes what rests on the robot, before the robot goes or moves: it falls.
  void wakeWhatRestsOnIt();
  /// Couples a mimic joint to the joint it follows, as strongly as its max_effort.
  void couple(Joint& follower);

  ModelSpec spec_;
  std::string name_;
  btMultiBodyDynamicsWorld& world_;
  double dt_ = 0.001;
  std::vector<RobotPart> parts_;
  std::vector<PartFrames> frames_;
  std::vector<int> parent_part_;
  std::vector<const JointSpec*> part_joint_;  ///< the moving joint leading to each part (nullptr for part 0)
  std::unordered_map<std::string, int> part_of_link_;
  std::vector<Joint> joints_;
  std::unordered_map<std::string, int> joint_index_;
  std::vector<std::pair<int, const LinkSpec*>> weightless_;  ///< links with <turnGravityOff>, and their part

  std::unique_ptr<Scratch> scratch_;
  std::unique_ptr<BulletShapes> shapes_;
  std::unique_ptr<SelfCollisionRule> self_collision_;  ///< which parts collide; the colliders ask it
  std::unique_ptr<btMultiBody> body_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders_;  ///< per part
  std::vector<CollisionNames> collision_names_;                      ///< per part, by child, for contacts
  /// Per part, per collision: its first compound child and how many it has (a mesh's convex parts).
  std::vector<std::vector<std::pair<int, int>>> child_ranges_;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> constraints_;
  std::vector<Eigen::Isometry3d> part_poses_;  ///< world pose of each part's frame, after the last step
  /// Per part: a force [N] at its centre of mass and a torque [N m], world axes, through the coming step.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> part_wrenches_;
};

}  // namespace bullet_sim
