// The `raycast` wheel model: the robot is one rigid body (every link's mass and collision, wheels excepted),
// and each wheel is a ray down to the static ground. A wheel in contact carries a stiff spring-damper (0.5 mm
// of sag at rest) and grips through friction-circle impulses: |friction| <= mu * N, against the slip between
// the ground and the wheel's rim. Drive plugins turn each wheel's spin with a velocity motor limited by their
// torque, against its joint's damping and friction, as in the `contact` model. Wheels on a swivel (casters)
// carry load but no friction. Other moving joints are kinematic: they sit where a plugin puts them (0
// otherwise).
//
// One body and a few rays per step make it several times faster than `contact`; wheels meet only static
// geometry (the chassis still collides with everything), so `contact` stays for scenes where wheels climb
// obstacles or other robots.
#pragma once

#include <LinearMath/btTransform.h>

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "bullet_sim/physics/robot_body.h"
#include "bullet_sim/sensing/ray_caster.h"
#include "physics/contacts.h"
#include "physics/robot_parts.h"

class btCompoundShape;
class btManifoldPoint;
class btMultiBodyDynamicsWorld;
class btRigidBody;

namespace bullet_sim {

class BulletShapes;

class RaycastRobot : public PhysicsRobot, private ContactTuner {
 public:
  /// Builds the robot with its root link at `root_pose` and adds its chassis to `world`; wheels find the
  /// ground in `ground`'s static bodies. Throws SpecError when the model cannot be simulated this way.
  /// `name` is the robot's, as contacts name its collisions (model::link::collision).
  RaycastRobot(ModelSpec spec, std::string name, btMultiBodyDynamicsWorld& world, const RayCaster& ground,
               const Eigen::Isometry3d& root_pose);
  ~RaycastRobot() override;
  RaycastRobot(const RaycastRobot&) = delete;
  RaycastRobot& operator=(const RaycastRobot&) = delete;

  void beforeSubstep(double substep) override;
  void afterStep() override;
  SubstepLimit substepLimit() const override;
  double elasticEnergy() const override;
  void reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) override;
  void teleport(const Eigen::Isometry3d& root_pose) override;
  void setJointPositions(const JointPositions& joints) override;
  void setStepSize(double step_size) override;

  const ModelSpec& spec() const override { return spec_; }
  int jointIndex(const std::string& joint) const override;
  double jointPosition(int joint) const override { return joints_.at(joint).position; }
  double jointVelocity(int joint) const override { return joints_.at(joint).velocity; }
  double jointEffort(int joint) const override { return joints_.at(joint).effort; }
  void setJointVelocity(int joint, double velocity, double max_effort) override;
  void setJointPosition(int joint, double position, double max_effort) override;
  /// Pushes a wheel's spin, on top of its motor; a kinematic joint has no dynamics to push, so it stays put.
  void setJointEffort(int joint, double effort) override;
  void setRootVelocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) override;
  void applyLinkWrench(const std::string& link, const Eigen::Vector3d& force,
                       const Eigen::Vector3d& torque) override;
  bool takesJointEffort(int joint) const override;
  void applyJointEffort(int joint, double effort) override;
  Eigen::Isometry3d linkPose(const std::string& link) const override;
  Eigen::Vector3d linkLinearVelocity(const std::string& link) const override;
  Eigen::Vector3d linkAngularVelocity(const std::string& link) const override;
  const std::vector<RobotPart>& parts() const override { return layout_.parts; }
  int partOf(const std::string& link) const override;
  Eigen::Isometry3d partPose(int part) const override;
  std::vector<CollisionContact> contacts(const CollisionSource& source) const override;

 private:
  struct Joint {
    const JointSpec* spec;
    int child_link;  ///< index into spec_.links
    int parent_link;
    int wheel = -1;       ///< index into wheels_, or -1 for a kinematic joint
    int leader = -1;      ///< index into joints_ of the joint it mimics, or -1
    double position = 0;  ///< [rad] or [m]
    double velocity = 0;  ///< [rad/s] or [m/s]; a kinematic joint moves at it
    double effort = 0;    ///< applied by the motor and pushed with in the last step
    /// setJointEffort's and applyJointEffort's, through the coming step (wheels only)
    double external_effort = 0;
  };
  struct Wheel {
    int joint;
    double radius;           ///< [m]
    double inertia;          ///< about the axle [kg m^2]
    double inverse_inertia;  ///< 1 / inertia: the passes multiply
    double friction;         ///< mu
    bool caster;             ///< on a swivel: load only
    double spin_target = 0;  ///< [rad/s]
    double max_torque = 0;   ///< [N m]; 0 = free; the joint's friction until a drive sets it
  };

  /// One direction of a wheel's contact, as a sequential-impulse row: fixed for the substep, so that each
  /// pass only takes dot products.
  struct Row {
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit, in the world frame
    Eigen::Vector3d arm = Eigen::Vector3d::Zero();  ///< offset x direction: how spin moves the point along it
    Eigen::Vector3d turn = Eigen::Vector3d::Zero();  ///< [rad/(s N s)] the spin a unit impulse along it gives
    /// [m/(s N s)] the velocity a unit impulse along it gives
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
    double inverse_mass = 0;      ///< [1/kg] the chassis's, felt at the point along it
  };
  /// A wheel's contact with the ground in one substep, and the impulses solved for it. A caster, which does
  /// not grip, builds only its normal row.
  struct Contact {
    Row normal, forward, lateral;  ///< the spring's (the chassis's up), rolling (positive spin), sideways
    double compression = 0;  ///< [m] of the spring
    double bias = 0;         ///< [m/s] the separating speed the spring asks for
    double softness = 0;     ///< [m/(N s)] how much each unit of impulse relaxes it
    double soft_mass = 0;    ///< [kg] the spring's effective mass: 1 / (normal's inverse mass + softness)
    double normal_mass = 0;  ///< [kg] 1 / the normal's inverse mass
    /// [kg] the one mass of both grip rows (pressWheels), while the motor holds the rim and while it slips
    double grip_mass_held = 0, grip_mass_free = 0;
    double friction = 0;     ///< mu: the lesser of the wheel's and the ground's, as Gazebo takes it
    double normal_impulse = 0, forward_impulse = 0, lateral_impulse = 0;
    double motor_impulse = 0;  ///< [N m s] on the wheel's spin this substep, within its torque budget
    bool on_ground = false;    ///< its ray found ground within the rim
    bool grips = false;        ///< on the ground and gripping (casters only carry load)
  };

  void buildWheels();
  /// Adds each wheel's rim to the chassis: its collision shape, a little smaller, so that walls stop it.
  void addWheelRims(btCompoundShape& compound);
  /// A driven wheel's rim contact rolls: friction along the rim holds its spinning surface to what it touches
  /// (a driven wheel against a wall climbs it), as the contact model's wheels do, within what the motor's
  /// torque can carry. The rim's reaction on the spin is left out: the motor holds it. A free wheel's rim has
  /// ordinary friction.
  bool tune(btManifoldPoint& point, int child, bool ours_is_a, bool joining) const override;
  /// Sums each wheel's rim's normal impulses in the last solve (into rim_impulse_weighed_).
  void weigh(const btManifoldPoint& point, int child) override;
  /// Casts each wheel's ray down from its hub; the root link is at `root`.
  void castWheelRays(const Eigen::Isometry3d& root);
  /// `spin` [rad/s] after the joint's damping over the substep: explicit from its start, as the contact model
  /// applies it, and stopping the wheel at most.
  double damped(const Wheel& wheel, double spin) const;
  /// Sets up each wheel's contact with the ground under it.
  void pressWheels(const Eigen::Isometry3d& root);
  /// Applies the impulses each wheel starts from (the last substep's) to the chassis and the wheels' spin.
  void warmStart();
  /// One pass of wheel `w`'s spring-damper impulse, solved implicitly.
  double supportWheel(size_t w);
  /// Caches the root pose after the chassis moved.
  void refreshPose();
  /// One pass of wheel `w`'s motor and friction impulses.
  double driveWheel(size_t w);
  /// The row along `direction` at `offset` from the chassis's centre of mass, with this step's inertia.
  Row row(const Eigen::Vector3d& offset, const Eigen::Vector3d& direction) const;
  /// The chassis's velocity along `row` at its point, as the wheels' passes have left it.
  double velocityAlong(const Row& row) const;
  /// Applies `impulse` [N s] along `row` to the passes' copy of the chassis's velocity.
  void push(const Row& row, double impulse);
  void buildChassis(const Eigen::Isometry3d& root_pose);
  /// Link frames in the root link's frame, from the joint positions; computed when asked for, after a change.
  const std::vector<Eigen::Isometry3d>& linkFrames() const;
  /// Where each wheel's hub is in the root frame, with its axle: only kinematic joints move them.
  void updateHubs();
  /// Puts each kinematic mimic joint where the joint it follows says (within its limits).
  void followLeaders();
  int linkIndex(const std::string& link) const;
  /// linkPose by the link's index in spec_.links, after the last step.
  Eigen::Isometry3d linkPoseAt(int link) const;
  /// The root link's pose in the world, from the chassis body's as it is now.
  Eigen::Isometry3d rootPose() const;

  ModelSpec spec_;
  std::string name_;
  btMultiBodyDynamicsWorld& world_;
  const RayCaster& ground_;
  double dt_;
  PartLayout layout_;
  std::vector<Joint> joints_;
  std::unordered_map<std::string, int> joint_index_;
  std::unordered_map<std::string, int> link_index_;
  /// Per spec_.joints entry: its child and parent link indices, and its index into joints_ (-1 when fixed).
  std::vector<int> tree_child_, tree_parent_, tree_moving_;
  std::vector<Wheel> wheels_;
  double mass_ = 0;
  std::vector<double> springs_;     ///< [N/m] per wheel
  std::vector<double> dampers_;     ///< [N s/m] per wheel
  double spring_frequency_ = 0;     ///< [rad/s] each wheel's spring with its share of the mass
  Eigen::Isometry3d root_to_body_;  ///< the chassis body's frame (com, principal axes) in the root link frame
  Eigen::Isometry3d body_to_root_;  ///< its inverse
  btTransform body_to_root_bullet_;  ///< body_to_root_, for Bullet's products
  mutable std::vector<Eigen::Isometry3d> link_in_root_;
  mutable bool frames_stale_ = true;
  /// Per link: it is in the root's part (only fixed joints join it to the root), so its frame in the root's
  /// never goes stale.
  std::vector<bool> fixed_to_root_;
  std::vector<int> part_root_links_;  ///< per part, its root link's index: every ray body's pose, every step
  bool hubs_stale_ = true;
  std::vector<Eigen::Isometry3d> hub_in_root_;  ///< per wheel
  Eigen::Isometry3d root_pose_;                 ///< world pose of the root link after the last step
  /// What plugins push the chassis with through the coming step: a force [N] at its centre of mass and a
  /// torque [N m], world axes.
  Eigen::Vector3d step_force_ = Eigen::Vector3d::Zero(), step_torque_ = Eigen::Vector3d::Zero();

  std::unique_ptr<BulletShapes> shapes_;
  std::unique_ptr<btRigidBody> chassis_;
  std::vector<CollisionSource> chassis_sources_;  ///< per child shape of the chassis
  std::vector<int> rim_children_;                 ///< per wheel: its rim's child index in the chassis
  CollisionNames chassis_names_;
  // Per step scratch, kept to avoid allocating.
  std::vector<Eigen::Vector3d> ray_origins_, ray_directions_;
  std::vector<double> ray_hits_;
  std::vector<Eigen::Vector3d> ray_normals_;
  std::vector<double> ray_frictions_;  ///< the mu of the ground each ray hit
  std::vector<Contact> contacts_;    ///< per wheel
  std::vector<double> rim_normal_impulse_;  ///< [N s] per wheel: what its rim met took in the last solve
  std::vector<double> rim_impulse_weighed_;  ///< [N s] per wheel: the same, as the world weighs it
  Eigen::Matrix3d inverse_inertia_;  ///< the chassis's, in the world frame, this step
  double gravity_speed_ = 0;  ///< [m/s] gravity's velocity change along the chassis's up this substep
  Eigen::Vector3d linear_velocity_ = Eigen::Vector3d::Zero();   ///< the chassis's, during the wheels' passes
  Eigen::Vector3d angular_velocity_ = Eigen::Vector3d::Zero();  ///< the chassis's, during the wheels' passes
};

}  // namespace bullet_sim
