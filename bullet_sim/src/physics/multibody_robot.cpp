#include "physics/multibody_robot.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyGearConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "bullet_shapes.h"
#include "bullet_sim/common/diagnostics.h"
#include "physics/robot_parts.h"
#include "physics/self_collision.h"
#include "physics/sleep.h"

namespace bullet_sim {

namespace {

// A motor's velocity gain, and the position and velocity gains of a joint held at a position. Bullet's motor
// corrects kp * (position error) / dt + kd * (velocity error) per step, within the impulse limit.
constexpr double kVelocityGain = 1.0;
constexpr double kHoldPositionGain = 0.2;
constexpr double kHoldVelocityGain = 1.0;
constexpr double kLightLinkTime = 0.02;  // [s] see substepLimit
// The share of a mimic follower's position error its coupling corrects per substep (with Bullet's erp2).
constexpr double kCouplingGain = 1.0;
}  // namespace

struct MultiBodyRobot::Scratch {
  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  std::vector<btVector3> omega;  ///< per part, in its Bullet frame: [0] base, [k] link k - 1
  std::vector<btVector3> velocity;
};

MultiBodyRobot::MultiBodyRobot(ModelSpec spec, std::string name, btMultiBodyDynamicsWorld& world,
                               const Eigen::Isometry3d& root_pose)
    : spec_(std::move(spec)),
      name_(std::move(name)),
      world_(world),
      scratch_(std::make_unique<Scratch>()),
      shapes_(std::make_unique<BulletShapes>()) {
  dt_ = world_.getSolverInfo().m_timeStep;
  buildParts();
  scratch_->omega.resize(parts_.size());
  scratch_->velocity.resize(parts_.size());
  buildMultiBody(root_pose);
}

MultiBodyRobot::~MultiBodyRobot() {
  wakeWhatRestsOnIt();  // its contacts go with it
  for (auto& constraint : constraints_) world_.removeMultiBodyConstraint(constraint.get());
  for (auto& collider : colliders_) world_.removeCollisionObject(collider.get());
  world_.removeMultiBody(body_.get());
}

void MultiBodyRobot::buildParts() {
  Diagnostics diagnostics(spec_.source);
  PartLayout layout = partitionAtMovingJoints(spec_);
  parts_ = std::move(layout.parts);
  parent_part_ = std::move(layout.parent);
  part_joint_ = std::move(layout.joint);
  part_of_link_ = std::move(layout.part_of_link);
  frames_.resize(parts_.size());
  for (size_t k = 0; k < parts_.size(); ++k) {
    PartFrames& frames = frames_[k];
    frames.link_in_part = std::move(layout.link_in_part[k]);
    std::vector<std::pair<std::string, Eigen::Isometry3d>> placed;
    for (const auto& name : parts_[k].links) placed.emplace_back(name, frames.link_in_part.at(name));
    const MassProperties mass = combineInertia(spec_, placed);
    if (mass.mass <= 0 && k == 0 && hasFixedBase(spec_)) {
      frames.mass = 1;  // a fixed base does not move: its mass does not matter, but Bullet wants one
      frames.principal_inertia = Eigen::Vector3d::Ones();
      continue;
    }
    if (!checkMovingPart(parts_[k], mass.mass, diagnostics)) continue;
    // Bullet's frame of a part: at its centre of mass, along its principal axes.
    frames.mass = mass.mass;
    frames.part_to_bullet = mass.principalFrame(&frames.principal_inertia);
    for (const auto& name : parts_[k].links) {
      const LinkSpec& link = *spec_.link(name);
      if (!link.gravity && link.inertial) weightless_.emplace_back(static_cast<int>(k), &link);
    }
  }
  diagnostics.throwIfErrors();
}

void MultiBodyRobot::buildMultiBody(const Eigen::Isometry3d& root_pose) {
  const int links = static_cast<int>(parts_.size()) - 1;
  body_ = std::make_unique<btMultiBody>(links, frames_[0].mass, toBullet(frames_[0].principal_inertia),
                                        /*fixedBase=*/hasFixedBase(spec_), /*canSleep=*/maySleep(spec_));
  body_->setSleepThreshold(kMultiBodySleepMotion);
  body_->setSleepTimeout(kSleepTime);
  body_->setBaseWorldTransform(toBullet(root_pose * frames_[0].part_to_bullet));
  std::vector<bool> self_collide;
  for (const RobotPart& part : parts_) {
    const auto flagged = [&](const std::string& link) { return spec_.link(link)->self_collide; };
    self_collide.push_back(std::any_of(part.links.begin(), part.links.end(), flagged));
  }
  self_collision_ = std::make_unique<SelfCollisionRule>(std::move(self_collide), parent_part_);
  for (int k = 1; k <= links; ++k) setupJoint(k);
  body_->finalizeMultiDof();
  body_->setLinearDamping(0);
  body_->setAngularDamping(0);
  body_->setUseGyroTerm(true);
  body_->setHasSelfCollision(self_collision_->any());
  world_.addMultiBody(body_.get());
  const std::vector<GazeboCollision> gazebo = gazeboCollisions(spec_);
  for (int k = 0; k <= links; ++k) {
    collision_names_.push_back(robotCollisionNames(name_, spec_, gazebo, parts_[k].sources));
  }
  child_ranges_.resize(parts_.size());
  for (int k = 0; k <= links; ++k) addCollider(k);

  for (auto& joint : joints_) {
    const JointSpec& spec = *joint.spec;
    if (spec.type != JointSpec::Type::kContinuous && std::isfinite(spec.lower) && std::isfinite(spec.upper)) {
      constraints_.push_back(std::make_unique<btMultiBodyJointLimitConstraint>(body_.get(), joint.bullet_link,
                                                                               spec.lower, spec.upper));
      world_.addMultiBodyConstraint(constraints_.back().get());
    }
    if (spec.friction > 0) motorFor(joint);  // dry joint friction: a motor holding zero velocity
  }
  for (auto& joint : joints_) couple(joint);
  reset(root_pose, {});
}

// Bullet's gear constraint holds q_follower + ratio * q_leader at a target: ratio -multiplier, target offset.
void MultiBodyRobot::couple(Joint& follower) {
  const auto& mimic = follower.spec->mimic;
  const auto leader = mimic ? joint_index_.find(mimic->joint) : joint_index_.end();
  if (leader == joint_index_.end()) return;
  const int leader_link = joints_[leader->second].bullet_link;
  auto coupling = std::make_unique<btMultiBodyGearConstraint>(
      body_.get(), follower.bullet_link, body_.get(), leader_link, btVector3(0, 0, 0), btVector3(0, 0, 0),
      btMatrix3x3::getIdentity(), btMatrix3x3::getIdentity());
  coupling->setGearRatio(-mimic->multiplier);
  coupling->setRelativePositionTarget(mimic->offset);
  coupling->setErp(kCouplingGain);
  coupling->setMaxAppliedImpulse(mimic->max_effort * dt_);
  coupling->finalizeMultiDof();  // as for motors: reading its effort needs Bullet's impulse buffer now
  follower.coupling = coupling.get();
  world_.addMultiBodyConstraint(coupling.get());
  constraints_.push_back(std::move(coupling));
}

void MultiBodyRobot::setupJoint(int k) {
  const JointSpec& joint = *part_joint_[k];
  const int parent = parent_part_[k];
  // The child part's frame at q = 0 in the parent's Bullet frame, and the child's Bullet frame in its part
  // frame.
  const Eigen::Isometry3d joint_in_parent =
      frames_[parent].part_to_bullet.inverse() * frames_[parent].link_in_part.at(joint.parent) * joint.origin;
  const Eigen::Isometry3d& child = frames_[k].part_to_bullet;
  const Eigen::Matrix3d child_in_parent = joint_in_parent.linear() * child.linear();
  const Eigen::Quaterniond parent_to_child(child_in_parent.transpose());
  const btQuaternion rotation(parent_to_child.x(), parent_to_child.y(), parent_to_child.z(),
                              parent_to_child.w());
  const btVector3 axis = toBullet(child.linear().transpose() * joint.axis);
  const btVector3 parent_com_to_pivot = toBullet(joint_in_parent.translation());
  const btVector3 pivot_to_com = toBullet(child.linear().transpose() * child.translation());
  if (joint.type == JointSpec::Type::kPrismatic) {
    body_->setupPrismatic(k - 1, frames_[k].mass, toBullet(frames_[k].principal_inertia), parent - 1,
                          rotation, axis, parent_com_to_pivot, pivot_to_com, /*disableParentCollision=*/true);
  } else {
    body_->setupRevolute(k - 1, frames_[k].mass, toBullet(frames_[k].principal_inertia), parent - 1, rotation,
                         axis, parent_com_to_pivot, pivot_to_com, /*disableParentCollision=*/true);
  }
  joint_index_[joint.name] = static_cast<int>(joints_.size());
  joints_.push_back({&joint, k - 1, jointInertia(k)});
}

double MultiBodyRobot::jointInertia(int k) const {
  const JointSpec& joint = *part_joint_[k];
  const PartFrames& frames = frames_[k];
  if (joint.type == JointSpec::Type::kPrismatic) return frames.mass;
  const Eigen::Isometry3d joint_in_part = frames.link_in_part.at(joint.child);
  const Eigen::Vector3d axis = (joint_in_part.linear() * joint.axis).normalized();
  const Eigen::Matrix3d to_part = frames.part_to_bullet.linear();
  const Eigen::Matrix3d inertia = to_part * frames.principal_inertia.asDiagonal() * to_part.transpose();
  const Eigen::Vector3d offset = frames.part_to_bullet.translation() - joint_in_part.translation();
  return axis.dot(inertia * axis) + frames.mass * offset.cross(axis).squaredNorm();
}

void MultiBodyRobot::addCollider(int k) {
  auto collider = std::make_unique<RuledLinkCollider>(body_.get(), k - 1, *self_collision_);
  if (parts_[k].collisions.empty()) {
    // Bullet solves a link's motors in its collider's simulation island, so a part without collisions still
    // gets a collider: a point that collides with nothing.
    Shape point;
    point.type = Shape::Type::kSphere;
    point.radius = 1e-3;
    collider->setCollisionShape(shapes_->make(point, true));
    world_.addCollisionObject(collider.get(), 0, 0);
  } else {
    const Eigen::Isometry3d bullet_to_part = frames_[k].part_to_bullet.inverse();
    btCompoundShape* compound = shapes_->makeCompound(toBullet(bullet_to_part));  // bounds along the part
    CollisionNames by_child;  // a mesh's convex parts are children of their own
    // A fixed base never moves: its meshes collide by their triangles, as the world's meshes do.
    const bool still = spec_.is_static || (k == 0 && hasFixedBase(spec_));
    for (size_t c = 0; c < parts_[k].collisions.size(); ++c) {
      const Collision& collision = parts_[k].collisions[c];
      const int first = compound->getNumChildShapes();
      const int count =
          shapes_->addTo(*compound, toBullet(bullet_to_part * collision.origin), collision.shape, !still);
      child_ranges_[k].emplace_back(first, count);
      by_child.append(collision_names_[k], c, count);
    }
    collision_names_[k] = std::move(by_child);
    compound->recalculateLocalAabb();
    collider->setCollisionShape(compound);
    const SurfaceSpec& surface = spec_.link(parts_[k].root_link)->surface;
    collider->setFriction(surface.mu1);
    collider->setRestitution(0);
    if (surface.kp || surface.kd) {
      // Gazebo's defaults: a rigid contact (kp 1e12 N/m) with kd 1 N s/m.
      collider->setContactStiffnessAndDamping(surface.kp.value_or(1e12), surface.kd.value_or(1.0));
    }
    // A fixed base is static geometry: it meets the robots, not the world's other static geometry.
    if (still) {
      world_.addCollisionObject(collider.get(), kStaticGroup, kRobotGroup);
    } else {
      world_.addCollisionObject(collider.get(), kRobotGroup, kStaticGroup | kRobotGroup);
    }
  }
  nameCollisions(*collider, collision_names_[k]);
  if (k == 0) {
    body_->setBaseCollider(collider.get());
  } else {
    body_->getLink(k - 1).m_collider = collider.get();
  }
  colliders_.push_back(std::move(collider));
}

btMultiBodyJointMotor* MultiBodyRobot::motorFor(Joint& joint) {
  if (!joint.motor) {
    auto motor = std::make_unique<btMultiBodyJointMotor>(body_.get(), joint.bullet_link, 0.0,
                                                         joint.spec->friction * dt_);
    motor->finalizeMultiDof();  // Bullet sizes its impulse buffer lazily; reading the effort needs it now
    joint.motor = motor.get();
    world_.addMultiBodyConstraint(motor.get());
    constraints_.push_back(std::move(motor));
  }
  return joint.motor;
}

void MultiBodyRobot::beforeSubstep(double substep) {
  for (const auto& joint : joints_) {
    // Explicit, and at most what stops the joint within the substep: a damping too strong for the substeps
    // physics runs (1e6 on a caster's swivel wants far more than kMaxSubsteps) reversed the joint faster at
    // each one and flung the robot; held so, it holds the joint still.
    const double coefficient = std::min(joint.spec->damping, joint.inertia / substep);
    const double damping = coefficient > 0 ? coefficient * body_->getJointVel(joint.bullet_link) : 0.0;
    if (joint.step_effort != 0 || damping != 0)
      body_->addJointTorque(joint.bullet_link, joint.step_effort - damping);
  }
  for (size_t k = 0; k < parts_.size(); ++k) {
    const auto& [force, torque] = part_wrenches_[k];
    if (force.isZero() && torque.isZero()) continue;
    if (k == 0) {
      body_->addBaseForce(toBullet(force));
      body_->addBaseTorque(toBullet(torque));
    } else {
      body_->addLinkForce(static_cast<int>(k) - 1, toBullet(force));
      body_->addLinkTorque(static_cast<int>(k) - 1, toBullet(torque));
    }
  }
  // <turnGravityOff>: Bullet pulls every link, so such links get their weight back as an upward force.
  const Eigen::Vector3d gravity = fromBullet(world_.getGravity());
  for (const auto& [part, link] : weightless_) {
    const Eigen::Vector3d force = -link->inertial->mass * gravity;
    const Eigen::Isometry3d& pose = part_poses_[part];
    const Eigen::Vector3d lever = pose * (frames_[part].link_in_part.at(link->name) * link->inertial->com) -
                                  pose * frames_[part].part_to_bullet.translation();
    if (part == 0) {
      body_->addBaseForce(toBullet(force));
      body_->addBaseTorque(toBullet(lever.cross(force)));
    } else {
      body_->addLinkForce(part - 1, toBullet(force));
      body_->addLinkTorque(part - 1, toBullet(lever.cross(force)));
    }
  }
}

SubstepLimit MultiBodyRobot::substepLimit() const {
  // Joint damping is applied explicitly, as a torque from the substep's start: it stays accurate (and far
  // from its stability bound, 2 I / c) while c h / I <= 1, I the moment of the part it turns about the axis.
  SubstepLimit limit;
  for (size_t k = 1; k < parts_.size(); ++k) {
    const JointSpec& joint = *part_joint_[k];
    if (joint.damping <= 0 || joint.type == JointSpec::Type::kPrismatic) continue;
    const double moment = joints_[k - 1].inertia;  // setupJoint(k) added joint k - 1
    const double seconds = moment / joint.damping;
    if (seconds >= limit.seconds) continue;
    std::ostringstream reason;
    reason << "joint [" << joint.name << "]'s damping of " << joint.damping << " on " << moment << " kg m^2";
    limit = {seconds, reason.str()};
  }
  // A light link that touches the world carries impulses of the robot's weight: the lighter it is, the
  // faster they swing it about (a caster's swivel), and the solver follows it only with shorter substeps.
  // kLightLinkTime * sqrt(m / M) holds a 1.1 kg robot on 10 g casters straight at 2 m/s (1.9 ms).
  double total = 0;
  for (const auto& frames : frames_) total += frames.mass;
  for (size_t k = 1; k < parts_.size(); ++k) {
    if (parts_[k].collisions.empty()) continue;
    const double seconds = kLightLinkTime * std::sqrt(frames_[k].mass / total);
    if (seconds >= limit.seconds) continue;
    std::ostringstream reason;
    reason << "link [" << parts_[k].root_link << "] of " << frames_[k].mass << " kg on a robot of "
           << total << " kg";
    limit = {seconds, reason.str()};
  }
  return limit;
}

void MultiBodyRobot::afterStep() {
  for (auto& joint : joints_) {
    joint.applied_effort = joint.pending_effort;
    joint.pending_effort = joint.step_effort = 0;
  }
  for (auto& wrench : part_wrenches_) wrench = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  if (sleeping()) return;  // Bullet moved none of it
  body_->forwardKinematics(scratch_->world_to_local, scratch_->local_origin);
  for (size_t k = 0; k < parts_.size(); ++k) {
    const btTransform pose =
        k == 0 ? body_->getBaseWorldTransform() : body_->getLink(k - 1).m_cachedWorldTransform;
    part_poses_[k] = fromBullet(pose) * frames_[k].part_to_bullet.inverse();
  }
}

void MultiBodyRobot::wakeWhatRestsOnIt() {
  std::vector<const btCollisionObject*> colliders;
  for (const auto& collider : colliders_) colliders.push_back(collider.get());
  wakeTouching(world_, colliders);
}

void MultiBodyRobot::reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) {
  wakeWhatRestsOnIt();
  wake(*body_);
  body_->setBaseWorldTransform(toBullet(root_pose * frames_[0].part_to_bullet));
  body_->setBaseVel(btVector3(0, 0, 0));
  body_->setBaseOmega(btVector3(0, 0, 0));
  for (auto& joint : joints_) {
    body_->setJointPos(joint.bullet_link, 0);
    body_->setJointVel(joint.bullet_link, 0);
    joint.pending_effort = joint.applied_effort = 0;
    if (joint.motor) {
      joint.motor->setVelocityTarget(0, kVelocityGain);
      joint.motor->setPositionTarget(0, 0);
      joint.motor->setMaxAppliedImpulse(joint.spec->friction * dt_);
    }
  }
  for (const auto& [joint, position] : joints) body_->setJointPos(joints_.at(joint).bullet_link, position);
  body_->clearForcesAndTorques();
  body_->updateCollisionObjectWorldTransforms(scratch_->world_to_local, scratch_->local_origin);
  part_poses_.resize(parts_.size());
  part_wrenches_.assign(parts_.size(), {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  afterStep();
}

void MultiBodyRobot::teleport(const Eigen::Isometry3d& root_pose) {
  wakeWhatRestsOnIt();
  wake(*body_);
  body_->setBaseWorldTransform(toBullet(root_pose * frames_[0].part_to_bullet));
  body_->updateCollisionObjectWorldTransforms(scratch_->world_to_local, scratch_->local_origin);
  afterStep();
}

void MultiBodyRobot::setJointPositions(const JointPositions& joints) {
  wake(*body_);
  for (const auto& [joint, position] : joints) {
    body_->setJointPos(joints_.at(joint).bullet_link, position);
    body_->setJointVel(joints_.at(joint).bullet_link, 0);
  }
  body_->updateCollisionObjectWorldTransforms(scratch_->world_to_local, scratch_->local_origin);
  afterStep();
}

void MultiBodyRobot::setStepSize(double step_size) {
  for (auto& joint : joints_) {
    if (joint.motor) joint.motor->setMaxAppliedImpulse(joint.motor->getMaxAppliedImpulse() * step_size / dt_);
    if (joint.coupling) joint.coupling->setMaxAppliedImpulse(joint.spec->mimic->max_effort * step_size);
  }
  dt_ = step_size;
}

bool MultiBodyRobot::sleeping() const {
  return !colliders_.empty() && colliders_.front()->getActivationState() == ISLAND_SLEEPING;
}

int MultiBodyRobot::jointIndex(const std::string& joint) const {
  const auto found = joint_index_.find(joint);
  return found == joint_index_.end() ? -1 : found->second;
}

double MultiBodyRobot::jointPosition(int joint) const {
  return body_->getJointPos(joints_.at(joint).bullet_link);
}

double MultiBodyRobot::jointVelocity(int joint) const {
  return body_->getJointVel(joints_.at(joint).bullet_link);
}

double MultiBodyRobot::jointEffort(int joint) const {
  const Joint& state = joints_.at(joint);
  auto* motor = state.motor;  // Bullet's getters are not const
  auto* coupling = state.coupling;
  return state.applied_effort + (motor ? motor->getAppliedImpulse(0) / dt_ : 0.0) +
         (coupling ? coupling->getAppliedImpulse(0) / dt_ : 0.0);
}

void MultiBodyRobot::setJointVelocity(int joint, double velocity, double max_effort) {
  btMultiBodyJointMotor* motor = motorFor(joints_.at(joint));
  motor->setPositionTarget(0, 0);
  motor->setVelocityTarget(velocity, kVelocityGain);
  motor->setMaxAppliedImpulse(max_effort * dt_);
}

void MultiBodyRobot::setJointPosition(int joint, double position, double max_effort) {
  btMultiBodyJointMotor* motor = motorFor(joints_.at(joint));
  motor->setPositionTarget(position, kHoldPositionGain);
  motor->setVelocityTarget(0, kHoldVelocityGain);
  motor->setMaxAppliedImpulse(max_effort * dt_);
}

void MultiBodyRobot::setJointEffort(int joint, double effort) {
  Joint& target = joints_.at(joint);  // its motor does what it was last told, as Gazebo's SetForce leaves it
  target.step_effort += effort;
  target.pending_effort += effort;
}

// As Gazebo's Model::SetLinearVel and SetAngularVel give every link the same velocities, the joints stop.
void MultiBodyRobot::setRootVelocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
  if (spec_.is_static) return;  // a static model never moves by itself
  wake(*body_);
  if (hasFixedBase(spec_)) {      // its base stays; its joints stop, as every link takes the base's twist
    for (const auto& joint : joints_) body_->setJointVel(joint.bullet_link, 0);
    return;
  }
  const Eigen::Vector3d origin = linkPose(spec_.root).translation();
  const Eigen::Vector3d com = part_poses_[0] * frames_[0].part_to_bullet.translation();
  body_->setBaseVel(toBullet(linear + angular.cross(com - origin)));
  body_->setBaseOmega(toBullet(angular));
  for (const auto& joint : joints_) body_->setJointVel(joint.bullet_link, 0);
}

void MultiBodyRobot::applyLinkWrench(const std::string& link, const Eigen::Vector3d& force,
                                     const Eigen::Vector3d& torque) {
  const int part = partOf(link);
  if (part < 0) throw std::out_of_range("no link [" + link + "] in model [" + spec_.name + "]");
  // Bullet takes forces at a part's centre of mass: the force moved there brings its moment about it.
  const Eigen::Vector3d com = part_poses_[part] * frames_[part].part_to_bullet.translation();
  const Eigen::Vector3d moment = torque + (linkPose(link).translation() - com).cross(force);
  part_wrenches_[part].first += force;
  part_wrenches_[part].second += moment;
  wake(*body_);
}

bool MultiBodyRobot::takesJointEffort(int joint) const {
  return joint >= 0 && joint < static_cast<int>(joints_.size());
}

void MultiBodyRobot::applyJointEffort(int joint, double effort) { joints_.at(joint).step_effort += effort; }

Eigen::Isometry3d MultiBodyRobot::linkPose(const std::string& link) const {
  const int part = partOf(link);
  if (part < 0) throw std::out_of_range("no link [" + link + "] in model [" + spec_.name + "]");
  return part_poses_[part] * frames_[part].link_in_part.at(link);
}

Eigen::Vector3d MultiBodyRobot::linkAngularVelocity(const std::string& link) const {
  const int part = partOf(link);
  if (part < 0) throw std::out_of_range("no link [" + link + "] in model [" + spec_.name + "]");
  if (part == 0) return fromBullet(body_->getBaseOmega());
  body_->compTreeLinkVelocities(scratch_->omega.data(), scratch_->velocity.data());
  return part_poses_[part].linear() * frames_[part].part_to_bullet.linear() *
         fromBullet(scratch_->omega[part]);
}

Eigen::Vector3d MultiBodyRobot::linkLinearVelocity(const std::string& link) const {
  const int part = partOf(link);
  if (part < 0) throw std::out_of_range("no link [" + link + "] in model [" + spec_.name + "]");
  Eigen::Vector3d com_velocity, omega;
  if (part == 0) {
    com_velocity = fromBullet(body_->getBaseVel());
    omega = fromBullet(body_->getBaseOmega());
  } else {
    body_->compTreeLinkVelocities(scratch_->omega.data(), scratch_->velocity.data());
    const Eigen::Matrix3d bullet_rotation =
        part_poses_[part].linear() * frames_[part].part_to_bullet.linear();
    com_velocity = bullet_rotation * fromBullet(scratch_->velocity[part]);
    omega = bullet_rotation * fromBullet(scratch_->omega[part]);
  }
  const Eigen::Vector3d com = part_poses_[part] * frames_[part].part_to_bullet.translation();
  return com_velocity + omega.cross(linkPose(link).translation() - com);
}

int MultiBodyRobot::partOf(const std::string& link) const {
  const auto found = part_of_link_.find(link);
  return found == part_of_link_.end() ? -1 : found->second;
}

Eigen::Isometry3d MultiBodyRobot::partPose(int part) const { return part_poses_.at(part); }

std::vector<CollisionContact> MultiBodyRobot::contacts(const CollisionSource& source) const {
  const int part = partOf(source.link);
  if (part < 0) return {};
  const auto& sources = parts_[part].sources;
  const auto found = std::find(sources.begin(), sources.end(), source);
  if (found == sources.end()) return {};
  const auto [first, count] = child_ranges_[part].at(found - sources.begin());
  return contactsOf(world_, *colliders_[part], first, count, dt_);
}

}  // namespace bullet_sim
