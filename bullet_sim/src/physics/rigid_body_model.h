// A model with no moving joints (a crate, a box, a chair: one link, or links fixed together) as one Bullet
// rigid body, as ODE makes every body in Gazebo. Its contacts are Bullet's rigid-body rows, a few times
// cheaper to solve than a multibody's, and contacts it cannot reach within a step stay out of the solve.
#pragma once

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "bullet_sim/physics/robot_body.h"
#include "physics/contacts.h"

class btMultiBodyDynamicsWorld;
class btRigidBody;

namespace bullet_sim {

class BulletShapes;

/// Whether `model` is one rigid part that moves: no moving joints, neither static nor fixed to the world, and
/// every link with a mass under gravity (<turnGravityOff> is the multibody's).
bool isOneRigidBody(const ModelSpec& model);

class RigidBodyModel : public PhysicsRobot {
 public:
  /// Builds the body with its root link at `root_pose` and adds it to `world`. Throws SpecError when the
  /// model cannot be simulated (no mass, a plane); `world` is untouched then. `model` must be one rigid
  /// body (isOneRigidBody); `name` is the model's, as contacts name its collisions (model::link::collision).
  RigidBodyModel(ModelSpec model, std::string name, btMultiBodyDynamicsWorld& world,
                 const Eigen::Isometry3d& root_pose);
  ~RigidBodyModel() override;
  RigidBodyModel(const RigidBodyModel&) = delete;
  RigidBodyModel& operator=(const RigidBodyModel&) = delete;

  void beforeSubstep(double substep) override;
  void afterStep() override;
  SubstepLimit substepLimit() const override { return {}; }
  void reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) override;
  void teleport(const Eigen::Isometry3d& root_pose) override;
  void setJointPositions(const JointPositions& joints) override;
  void setStepSize(double step_size) override { dt_ = step_size; }
  bool sleeping() const override;

  const ModelSpec& spec() const override { return spec_; }
  int jointIndex(const std::string&) const override { return -1; }  ///< it has no moving joints
  double jointPosition(int joint) const override { throw noJoint(joint); }
  double jointVelocity(int joint) const override { throw noJoint(joint); }
  double jointEffort(int joint) const override { throw noJoint(joint); }
  void setJointVelocity(int joint, double, double) override { throw noJoint(joint); }
  void setJointPosition(int joint, double, double) override { throw noJoint(joint); }
  void setJointEffort(int joint, double) override { throw noJoint(joint); }
  void setRootVelocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) override;
  void applyLinkWrench(const std::string& link, const Eigen::Vector3d& force,
                       const Eigen::Vector3d& torque) override;
  bool takesJointEffort(int) const override { return false; }
  void applyJointEffort(int joint, double) override { throw noJoint(joint); }
  Eigen::Isometry3d linkPose(const std::string& link) const override;
  Eigen::Vector3d linkLinearVelocity(const std::string& link) const override;
  Eigen::Vector3d linkAngularVelocity(const std::string& link) const override;
  const std::vector<RobotPart>& parts() const override { return parts_; }
  int partOf(const std::string& link) const override { return link_in_part_.count(link) ? 0 : -1; }
  Eigen::Isometry3d partPose(int part) const override;
  std::vector<CollisionContact> contacts(const CollisionSource& source) const override;

 private:
  std::out_of_range noJoint(int joint) const;
  /// The frame of link `link` in the part, or throws naming it.
  const Eigen::Isometry3d& linkInPart(const std::string& link) const;
  void buildBody(const Eigen::Isometry3d& root_pose);
  Eigen::Vector3d centreOfMass() const;  ///< [m] world

  ModelSpec spec_;
  std::string name_;
  btMultiBodyDynamicsWorld& world_;
  double dt_;
  std::vector<RobotPart> parts_;  ///< the one part
  std::unordered_map<std::string, Eigen::Isometry3d> link_in_part_;
  Eigen::Isometry3d part_to_body_ = Eigen::Isometry3d::Identity();  ///< Bullet's frame: com, principal axes
  Eigen::Isometry3d part_pose_ = Eigen::Isometry3d::Identity();     ///< world, after the last step
  /// Per collision of the part: its first compound child and how many it has (a mesh's convex parts).
  std::vector<std::pair<int, int>> child_ranges_;
  CollisionNames collision_names_;  ///< by compound child
  /// A force [N] at the centre of mass and a torque [N m], world axes, through the coming step.
  Eigen::Vector3d step_force_ = Eigen::Vector3d::Zero(), step_torque_ = Eigen::Vector3d::Zero();
  std::unique_ptr<BulletShapes> shapes_;
  std::unique_ptr<btRigidBody> body_;
};

}  // namespace bullet_sim
