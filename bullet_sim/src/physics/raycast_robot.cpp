#include "physics/raycast_robot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>

#include "bullet_shapes.h"
#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model_geometry.h"
#include "physics/multibody_robot.h"

namespace bullet_sim {

namespace {

constexpr double kSag = 0.0005;        // [m] suspension compression at rest: stiff, yet soft enough for 1 kHz
constexpr double kDampingRatio = 1.0;  // critically damped suspension
constexpr int kFrictionIterations = 4;  // sequential-impulse passes over the wheels per step
constexpr double kVerticalAxis = 0.9;   // |axis . up| above which a continuous joint is a caster swivel

Eigen::Isometry3d jointMotion(const JointSpec& joint, double position) {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  if (joint.type == JointSpec::Type::kPrismatic) {
    motion.translate(joint.axis * position);
  } else if (joint.moves()) {
    motion.rotate(Eigen::AngleAxisd(position, joint.axis));
  }
  return motion;
}

/// The radius of a link's wheel: its first collision is a sphere, or a cylinder along the joint axis.
std::optional<double> wheelRadius(const LinkSpec& link, const JointSpec& joint) {
  if (link.collisions.empty()) return std::nullopt;
  const Collision& collision = link.collisions.front();
  if (collision.shape.type == Shape::Type::kSphere) return collision.shape.radius;
  if (collision.shape.type != Shape::Type::kCylinder) return std::nullopt;
  const Eigen::Vector3d cylinder_axis = collision.origin.linear().col(2);
  if (std::abs(cylinder_axis.dot(joint.axis)) < 0.99) return std::nullopt;
  return collision.shape.radius;
}

}  // namespace

RaycastRobot::RaycastRobot(ModelSpec spec, std::string name, btMultiBodyDynamicsWorld& world,
                           const RayCaster& ground, const Eigen::Isometry3d& root_pose)
    : spec_(std::move(spec)),
      name_(std::move(name)),
      world_(world),
      ground_(ground),
      dt_(world.getSolverInfo().m_timeStep),
      shapes_(std::make_unique<BulletShapes>()) {
  layout_ = partitionAtMovingJoints(spec_);
  for (size_t i = 0; i < spec_.links.size(); ++i) link_index_[spec_.links[i].name] = static_cast<int>(i);
  for (const auto& joint : spec_.joints) {
    tree_child_.push_back(linkIndex(joint.child));
    tree_parent_.push_back(linkIndex(joint.parent));
    tree_moving_.push_back(joint.moves() ? static_cast<int>(joints_.size()) : -1);
    if (!joint.moves()) continue;
    joint_index_[joint.name] = static_cast<int>(joints_.size());
    joints_.push_back({&joint, linkIndex(joint.child), linkIndex(joint.parent)});
  }
  link_in_root_.resize(spec_.links.size(), Eigen::Isometry3d::Identity());
  buildWheels();
  buildChassis(root_pose);
  reset(root_pose, {});
}

RaycastRobot::~RaycastRobot() { world_.removeRigidBody(chassis_.get()); }

int RaycastRobot::linkIndex(const std::string& link) const { return link_index_.at(link); }

void RaycastRobot::buildWheels() {
  linkFrames();  // the zero pose
  for (size_t j = 0; j < joints_.size(); ++j) {
    Joint& joint = joints_[j];
    if (joint.spec->type != JointSpec::Type::kContinuous) continue;
    const LinkSpec& link = spec_.links[joint.child_link];
    const auto radius = wheelRadius(link, *joint.spec);
    if (!radius) continue;
    bool caster = false;  // a continuous joint about the vertical between the root and the wheel: a swivel
    for (const JointSpec* up = spec_.parentJoint(joint.spec->parent); up;
         up = spec_.parentJoint(up->parent)) {
      const Eigen::Vector3d axis = link_in_root_[linkIndex(up->child)].linear() * up->axis;
      caster |= up->type == JointSpec::Type::kContinuous && std::abs(axis.z()) > kVerticalAxis;
    }
    const double inertia =
        link.inertial ? joint.spec->axis.dot(link.inertial->inertia * joint.spec->axis) : 0.0;
    joint.wheel = static_cast<int>(wheels_.size());
    wheels_.push_back({static_cast<int>(j), *radius, std::max(inertia, 1e-6), link.surface.mu1, caster});
  }
  Diagnostics diagnostics(spec_.source);
  if (wheels_.empty()) {
    diagnostics.error(
        "the raycast wheel model found no wheels (continuous joints whose link collides as a sphere "
        "or a cylinder along the joint axis): use <wheelModel>contact</wheelModel>");
  }
  diagnostics.throwIfErrors();
  hub_in_root_.resize(wheels_.size());
  ray_origins_.resize(wheels_.size());
  ray_directions_.resize(wheels_.size());
  ray_hits_.resize(wheels_.size());
  contacts_.resize(wheels_.size());
}

void RaycastRobot::buildChassis(const Eigen::Isometry3d& root_pose) {
  std::vector<std::pair<std::string, Eigen::Isometry3d>> placed;
  for (size_t i = 0; i < spec_.links.size(); ++i) placed.emplace_back(spec_.links[i].name, link_in_root_[i]);
  const MassProperties mass = combineInertia(spec_, placed);
  if (mass.mass <= 0)
    throw SpecError(spec_.source, {"the robot has no mass: give its links <inertial> elements"});
  mass_ = mass.mass;
  Eigen::Vector3d moments;
  root_to_body_ = mass.principalFrame(&moments);

  // The chassis collides with everything but the wheels, which are rays.
  btCompoundShape* compound = shapes_->makeCompound();
  const Eigen::Isometry3d body_to_root = root_to_body_.inverse();
  for (size_t i = 0; i < spec_.links.size(); ++i) {
    const JointSpec* joint = spec_.parentJoint(spec_.links[i].name);
    if (joint && joint->moves() && joints_[joint_index_.at(joint->name)].wheel >= 0) continue;
    const auto& collisions = spec_.links[i].collisions;
    for (size_t c = 0; c < collisions.size(); ++c) {
      if (btCollisionShape* shape = shapes_->make(collisions[c].shape, true)) {
        compound->addChildShape(toBullet(body_to_root * link_in_root_[i] * collisions[c].origin), shape);
        chassis_sources_.push_back({spec_.links[i].name, static_cast<int>(c)});
      }
    }
  }
  chassis_names_ = robotCollisionNames(name_, gazeboCollisions(spec_), chassis_sources_);
  btRigidBody::btRigidBodyConstructionInfo info(mass_, nullptr, compound, toBullet(moments));
  info.m_friction = spec_.link(spec_.root)->surface.mu1;
  info.m_restitution = 0;
  chassis_ = std::make_unique<btRigidBody>(info);
  chassis_->setActivationState(DISABLE_DEACTIVATION);
  nameCollisions(*chassis_, chassis_names_);
  chassis_->setWorldTransform(toBullet(root_pose * root_to_body_));
  world_.addRigidBody(chassis_.get(), kRobotGroup, kStaticGroup | kRobotGroup);

  // Each wheel carries an equal share at rest with kSag of compression; critically damped.
  const double share = mass_ / static_cast<double>(wheels_.size());
  const double gravity = std::abs(world_.getGravity().z());
  spring_ = share * gravity / kSag;
  damper_ = 2 * kDampingRatio * std::sqrt(spring_ * share);
}

const std::vector<Eigen::Isometry3d>& RaycastRobot::linkFrames() const {
  if (!frames_stale_) return link_in_root_;
  link_in_root_[0] = Eigen::Isometry3d::Identity();
  for (size_t k = 0; k < spec_.joints.size(); ++k) {  // parents before children
    const JointSpec& joint = spec_.joints[k];
    const double position = tree_moving_[k] >= 0 ? joints_[tree_moving_[k]].position : 0.0;
    link_in_root_[tree_child_[k]] =
        link_in_root_[tree_parent_[k]] * joint.origin * jointMotion(joint, position);
  }
  frames_stale_ = false;
  return link_in_root_;
}

void RaycastRobot::updateHubs() {
  if (!hubs_stale_) return;
  const auto& frames = linkFrames();
  for (size_t w = 0; w < wheels_.size(); ++w) hub_in_root_[w] = frames[joints_[wheels_[w].joint].child_link];
  hubs_stale_ = false;
}

void RaycastRobot::beforeStep() {
  for (auto& joint : joints_) {
    if (joint.wheel < 0 && joint.velocity != 0) {  // kinematic joints move at their velocity
      joint.position += joint.velocity * dt_;
      hubs_stale_ = frames_stale_ = true;
    }
  }
  updateHubs();
  const Eigen::Isometry3d root = fromBullet(chassis_->getWorldTransform()) * root_to_body_.inverse();
  castWheelRays(root);
  const btMatrix3x3& inverse_inertia = chassis_->getInvInertiaTensorWorld();
  for (int r = 0; r < 3; ++r) inverse_inertia_.row(r) = fromBullet(inverse_inertia[r]);
  // The suspension, then the motors and friction together: sequential impulses over the wheels, with each
  // motor's impulse held within torque * dt and each contact's within the friction circle.
  for (const auto& wheel : wheels_) {  // efforts from outside the drive (the world API's) spin the wheels
    Joint& joint = joints_[wheel.joint];
    joint.velocity += joint.external_effort * dt_ / wheel.inertia;
    joint.external_effort = 0;
  }
  pressWheels(root);
  for (int pass = 0; pass < kFrictionIterations; ++pass) {
    for (size_t w = 0; w < wheels_.size(); ++w) driveWheel(w);
  }
  for (size_t w = 0; w < wheels_.size(); ++w) {
    Joint& joint = joints_[wheels_[w].joint];
    joint.effort = contacts_[w].motor_impulse / dt_;
    joint.position += joint.velocity * dt_;
  }
}

void RaycastRobot::castWheelRays(const Eigen::Isometry3d& root) {
  const Eigen::Vector3d up = root.linear().col(2);
  for (size_t w = 0; w < wheels_.size(); ++w) {
    ray_origins_[w] = root * hub_in_root_[w].translation();
    ray_directions_[w] = -up;
  }
  // A ray reaches one radius below the rim, so a wheel finds the ground before it lands.
  double reach = 0;
  for (const auto& wheel : wheels_) reach = std::max(reach, 2 * wheel.radius);
  ground_.castStatic(ray_origins_, ray_directions_, reach, ray_hits_);
}

inline Eigen::Vector3d RaycastRobot::velocityAt(const Eigen::Vector3d& offset) const {
  return fromBullet(chassis_->getLinearVelocity()) + fromBullet(chassis_->getAngularVelocity()).cross(offset);
}

inline double RaycastRobot::inverseMass(const Eigen::Vector3d& offset, const Eigen::Vector3d& direction) const {
  const Eigen::Vector3d arm = offset.cross(direction);
  return 1 / mass_ + arm.dot(inverse_inertia_ * arm);
}

void RaycastRobot::pressWheels(const Eigen::Isometry3d& root) {
  const Eigen::Vector3d up = root.linear().col(2);
  const Eigen::Vector3d com = fromBullet(chassis_->getWorldTransform().getOrigin());
  for (size_t w = 0; w < wheels_.size(); ++w) {
    Wheel& wheel = wheels_[w];
    Contact& contact = contacts_[w];
    contact = Contact{};
    const double compression = wheel.radius - ray_hits_[w];
    if (!(compression > 0)) continue;  // in the air (a miss is +inf)
    const Eigen::Vector3d point = ray_origins_[w] - up * ray_hits_[w];
    contact.offset = point - com;
    const double closing = -velocityAt(contact.offset).dot(up);  // [m/s] towards the ground
    const double force = std::max(0.0, spring_ * compression + damper_ * closing);
    contact.normal_impulse = force * dt_;
    chassis_->applyImpulse(toBullet(up * contact.normal_impulse), toBullet(contact.offset));
    const Eigen::Vector3d axis = root.linear() * hub_in_root_[w].linear() * joints_[wheel.joint].spec->axis;
    contact.forward = axis.cross(up).normalized();  // where a positive spin rolls the wheel
    contact.lateral = up.cross(contact.forward);
    contact.touching = !wheel.caster;
  }
}

void RaycastRobot::driveWheel(size_t w) {
  Contact& contact = contacts_[w];
  Wheel& wheel = wheels_[w];
  Joint& joint = joints_[wheel.joint];
  const double budget = wheel.max_torque * dt_;
  if (wheel.max_torque > 0) {
    const double wanted = wheel.pushed ? std::copysign(budget, wheel.spin_target)
                                       : contact.motor_impulse + (wheel.spin_target - joint.velocity) * wheel.inertia;
    const double total = std::clamp(wanted, -budget, budget);
    joint.velocity += (total - contact.motor_impulse) / wheel.inertia;
    contact.motor_impulse = total;
  }
  if (!contact.touching) return;
  const Eigen::Vector3d velocity = velocityAt(contact.offset);
  // Slip of the chassis over the rim, and the impulses that would cancel it (the rim shares the forward one).
  const double forward_slip = velocity.dot(contact.forward) - joint.velocity * wheel.radius;
  const double lateral_slip = velocity.dot(contact.lateral);
  // While its motor has torque to spare, the motor holds the rim: the chassis takes the whole impulse.
  const bool held = wheel.max_torque > 0 && std::abs(contact.motor_impulse) < budget;
  const double forward_mass = 1 / (inverseMass(contact.offset, contact.forward) +
                                   (held ? 0.0 : wheel.radius * wheel.radius / wheel.inertia));
  const double lateral_mass = 1 / inverseMass(contact.offset, contact.lateral);
  Eigen::Vector2d total(contact.forward_impulse - forward_slip * forward_mass,
                        contact.lateral_impulse - lateral_slip * lateral_mass);
  const double limit = wheel.friction * contact.normal_impulse;  // the friction circle
  if (total.norm() > limit) total *= limit / total.norm();
  const Eigen::Vector2d change = total - Eigen::Vector2d(contact.forward_impulse, contact.lateral_impulse);
  contact.forward_impulse = total.x();
  contact.lateral_impulse = total.y();
  chassis_->applyImpulse(toBullet(contact.forward * change.x() + contact.lateral * change.y()),
                         toBullet(contact.offset));
  // The rim feels the reaction; a holding motor takes what it can, the rest turns the wheel.
  const double reaction = wheel.radius * change.x();
  const double motor =
      held ? std::clamp(contact.motor_impulse + reaction, -budget, budget) : contact.motor_impulse;
  joint.velocity -= (reaction - (motor - contact.motor_impulse)) / wheel.inertia;
  contact.motor_impulse = motor;
}

void RaycastRobot::afterStep() {
  frames_stale_ = true;  // the wheels turned
  root_pose_ = fromBullet(chassis_->getWorldTransform()) * root_to_body_.inverse();
}

void RaycastRobot::reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) {
  for (auto& joint : joints_) joint.position = joint.velocity = joint.effort = joint.external_effort = 0;
  for (const auto& [joint, position] : joints) joints_.at(joint).position = position;
  for (auto& wheel : wheels_) {
    wheel.spin_target = wheel.max_torque = 0;
    wheel.pushed = false;
  }
  hubs_stale_ = frames_stale_ = true;
  chassis_->setWorldTransform(toBullet(root_pose * root_to_body_));
  chassis_->setLinearVelocity(btVector3(0, 0, 0));
  chassis_->setAngularVelocity(btVector3(0, 0, 0));
  chassis_->clearForces();
  afterStep();
}

void RaycastRobot::teleport(const Eigen::Isometry3d& root_pose) {
  chassis_->setWorldTransform(toBullet(root_pose * root_to_body_));
  afterStep();
}

void RaycastRobot::setJointPositions(const JointPositions& joints) {
  for (const auto& [joint, position] : joints) {
    joints_.at(joint).position = position;
    joints_.at(joint).velocity = 0;
  }
  hubs_stale_ = frames_stale_ = true;
}

void RaycastRobot::setStepSize(double step_size) { dt_ = step_size; }

int RaycastRobot::jointIndex(const std::string& joint) const {
  const auto found = joint_index_.find(joint);
  return found == joint_index_.end() ? -1 : found->second;
}

void RaycastRobot::setJointVelocity(int joint, double velocity, double max_effort) {
  Joint& target = joints_.at(joint);
  if (target.wheel >= 0) {
    wheels_[target.wheel].spin_target = velocity;
    wheels_[target.wheel].max_torque = max_effort;
    wheels_[target.wheel].pushed = false;
  } else {
    target.velocity = velocity;
  }
}

void RaycastRobot::setJointPosition(int joint, double position, double) {
  Joint& target = joints_.at(joint);
  if (target.wheel >= 0) {
    setJointVelocity(joint, 0, target.spec->effort);  // a wheel held still brakes
    return;
  }
  const double held = std::clamp(position, target.spec->lower, target.spec->upper);
  if (held != target.position) hubs_stale_ = frames_stale_ = true;
  target.position = held;
  target.velocity = 0;
}

void RaycastRobot::setJointEffort(int joint, double effort) {
  Joint& target = joints_.at(joint);
  if (target.wheel < 0) {
    target.velocity = 0;
    return;
  }
  Wheel& wheel = wheels_[target.wheel];
  wheel.spin_target = effort;  // only its sign counts
  wheel.max_torque = std::abs(effort);
  wheel.pushed = true;
}

// As Gazebo's Model::SetLinearVel and SetAngularVel give every link the same velocities, the joints stop.
void RaycastRobot::setRootVelocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
  const Eigen::Vector3d com = fromBullet(chassis_->getWorldTransform().getOrigin());
  chassis_->setLinearVelocity(toBullet(linear + angular.cross(com - root_pose_.translation())));
  chassis_->setAngularVelocity(toBullet(angular));
  for (auto& joint : joints_) joint.velocity = 0;
}

void RaycastRobot::applyLinkWrench(const std::string& link, const Eigen::Vector3d& force,
                                   const Eigen::Vector3d& torque) {
  const Eigen::Vector3d com = fromBullet(chassis_->getWorldTransform().getOrigin());
  chassis_->applyForce(toBullet(force), toBullet(linkPose(link).translation() - com));
  chassis_->applyTorque(toBullet(torque));
}

bool RaycastRobot::takesJointEffort(int joint) const {
  return joint >= 0 && joint < static_cast<int>(joints_.size()) && joints_[joint].wheel >= 0;
}

void RaycastRobot::applyJointEffort(int joint, double effort) {
  if (takesJointEffort(joint)) joints_[joint].external_effort += effort;
}

Eigen::Isometry3d RaycastRobot::linkPose(const std::string& link) const {
  const auto found = link_index_.find(link);
  if (found == link_index_.end())
    throw std::out_of_range("no link [" + link + "] in model [" + spec_.name + "]");
  return root_pose_ * linkFrames()[found->second];
}

Eigen::Vector3d RaycastRobot::linkLinearVelocity(const std::string& link) const {
  const Eigen::Vector3d com = fromBullet(chassis_->getWorldTransform().getOrigin());
  return fromBullet(chassis_->getLinearVelocity()) +
         fromBullet(chassis_->getAngularVelocity()).cross(linkPose(link).translation() - com);
}

Eigen::Vector3d RaycastRobot::linkAngularVelocity(const std::string& link) const {
  Eigen::Vector3d omega = fromBullet(chassis_->getAngularVelocity());
  const JointSpec* joint = spec_.parentJoint(link);
  if (joint && joint->moves()) {
    const Joint& state = joints_[joint_index_.at(joint->name)];
    if (state.wheel >= 0) omega += linkPose(link).linear() * joint->axis * state.velocity;
  }
  return omega;
}

int RaycastRobot::partOf(const std::string& link) const {
  const auto found = layout_.part_of_link.find(link);
  return found == layout_.part_of_link.end() ? -1 : found->second;
}

Eigen::Isometry3d RaycastRobot::partPose(int part) const {
  return linkPose(layout_.parts.at(part).root_link);
}

std::vector<CollisionContact> RaycastRobot::contacts(const CollisionSource& source) const {
  const auto found = std::find(chassis_sources_.begin(), chassis_sources_.end(), source);
  if (found == chassis_sources_.end()) return {};  // a wheel: its ray is its contact
  return contactsOf(world_, *chassis_, static_cast<int>(found - chassis_sources_.begin()), dt_);
}

}  // namespace bullet_sim
