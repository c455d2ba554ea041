#include "physics/raycast_robot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <Eigen/Dense>

#include "bullet_shapes.h"
#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model_geometry.h"
#include "physics/multibody_robot.h"
#include "physics/sleep.h"

namespace bullet_sim {

namespace {

constexpr double kSag = 0.0005;        // [m] suspension compression at rest: stiff, yet soft enough for 1 kHz
constexpr double kDampingRatio = 1.0;  // critically damped suspension
constexpr double kStandardGravity = 9.80665;  // [m/s^2] the least the springs are sized for
constexpr int kIterations = 6;         // sequential-impulse passes over the wheels per substep, at most
constexpr double kConvergedImpulse = 1e-9;  // [N s] a pass that changes no impulse by more ends them
constexpr double kVerticalAxis = 0.9;   // |axis . up| above which a continuous joint is a caster swivel
// The suspension is integrated implicitly (stable at any substep); substeps of at most this fraction of its
// period over 2 pi keep it as springy and damped as it is meant to be.
constexpr double kSubstepsPerRadian = 5;
// [m/s] at most, the speed at which a wheel's spring pushes the chassis off the ground, as the world's
// contacts push penetrating bodies apart (PhysicsOptions::max_correcting_velocity): a wheel that finds the
// ground above its rim (spawned under it, or a ray that steps onto a higher floor) rises onto it without a
// leap.
constexpr double kMaxSeparatingSpeed = 0.1;
// A ray hit whose surface tilts more than this from the chassis's up is a wall, not ground: it carries
// nothing.
constexpr double kSteepestGround = 0.7;  // [rad], 40 degrees
// Each wheel also collides, with walls and obstacles, as a rim: its collision shape this much smaller, so
// that it clears the ground while the spring holds the wheel (twice the sag at rest); pressed further, it
// meets the ground as a rigid wheel would.
constexpr double kRimInset = 2 * kSag;  // [m]
constexpr double kRollingNormMin = 0.5;   // |axis x normal| below which a contact is on the rim's flat side

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

/// The load [N] each wheel carries at rest for the chassis to rest level, every spring at the same sag: the
/// shares nearest to equal that balance the weight and its moments about the centre of mass (`wheels`, the
/// wheels' ground points from it, level). A wheel the balance would lift keeps a tenth of an equal share.
std::vector<double> levelLoads(const std::vector<Eigen::Vector2d>& wheels, double weight) {
  const Eigen::Index n = static_cast<Eigen::Index>(wheels.size());
  Eigen::MatrixXd balance(3, n);
  for (Eigen::Index i = 0; i < n; ++i) balance.col(i) << 1.0, wheels[i].x(), wheels[i].y();
  const Eigen::VectorXd equal = Eigen::VectorXd::Constant(n, weight / n);
  const Eigen::Vector3d wanted(weight, 0, 0);
  const Eigen::Vector3d correction =
      (balance * balance.transpose()).completeOrthogonalDecomposition().solve(wanted - balance * equal);
  const Eigen::VectorXd loads = equal + balance.transpose() * correction;
  std::vector<double> clamped(n);
  for (Eigen::Index i = 0; i < n; ++i) clamped[i] = std::max(loads[i], 0.1 * weight / n);
  return clamped;
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
  for (auto& joint : joints_) {
    const auto& mimic = joint.spec->mimic;
    if (mimic && joint_index_.count(mimic->joint)) joint.leader = joint_index_.at(mimic->joint);
  }
  link_in_root_.resize(spec_.links.size(), Eigen::Isometry3d::Identity());
  for (const auto& link : spec_.links) fixed_to_root_.push_back(partOf(link.name) == 0);
  for (const auto& part : layout_.parts) part_root_links_.push_back(linkIndex(part.root_link));
  buildWheels();
  buildChassis(root_pose);
  reset(root_pose, {});
}

RaycastRobot::~RaycastRobot() {
  wakeTouching(world_, {chassis_.get()});  // what rests on it falls; its contacts go with it
  world_.removeRigidBody(chassis_.get());
}

int RaycastRobot::linkIndex(const std::string& link) const { return link_index_.at(link); }

Eigen::Isometry3d RaycastRobot::rootPose() const {
  return fromBullet(chassis_->getWorldTransform() * body_to_root_bullet_);  // Bullet's product inlines
}

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
    const double axle_inertia = std::max(inertia, 1e-6);
    wheels_.push_back(
        {static_cast<int>(j), *radius, axle_inertia, 1 / axle_inertia, link.surface.mu1, caster});
  }
  Diagnostics diagnostics(spec_.source);
  if (wheels_.empty()) {
    diagnostics.error(
        "the raycast wheel model found no wheels (continuous joints whose link collides as a sphere "
        "or a cylinder along the joint axis): use <wheelModel>contact</wheelModel>");
  }
  diagnostics.throwIfErrors();
  hub_in_root_.assign(wheels_.size(), Eigen::Isometry3d::Identity());
  ray_origins_.resize(wheels_.size());
  ray_directions_.resize(wheels_.size());
  ray_hits_.resize(wheels_.size());
  contacts_.resize(wheels_.size());
  rim_normal_impulse_.resize(wheels_.size());
  rim_impulse_weighed_.resize(wheels_.size());
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
  body_to_root_ = root_to_body_.inverse();
  body_to_root_bullet_ = toBulletExactly(body_to_root_);

  // The chassis collides with everything but the wheels, which are rays. Its bounds lie along the root link.
  btCompoundShape* compound = shapes_->makeCompound(toBullet(body_to_root_));
  for (size_t i = 0; i < spec_.links.size(); ++i) {
    const JointSpec* joint = spec_.parentJoint(spec_.links[i].name);
    if (joint && joint->moves() && joints_[joint_index_.at(joint->name)].wheel >= 0) continue;
    const auto& collisions = spec_.links[i].collisions;
    for (size_t c = 0; c < collisions.size(); ++c) {
      if (btCollisionShape* shape = shapes_->make(collisions[c].shape, true)) {
        compound->addChildShape(toBullet(body_to_root_ * link_in_root_[i] * collisions[c].origin), shape);
        chassis_sources_.push_back({spec_.links[i].name, static_cast<int>(c)});
      }
    }
  }
  addWheelRims(*compound);
  compound->recalculateLocalAabb();
  chassis_names_ = robotCollisionNames(name_, spec_, gazeboCollisions(spec_), chassis_sources_);
  chassis_names_.tuner = this;
  btRigidBody::btRigidBodyConstructionInfo info(mass_, nullptr, compound, toBullet(moments));
  info.m_friction = spec_.link(spec_.root)->surface.mu1;
  info.m_restitution = 0;
  chassis_ = std::make_unique<btRigidBody>(info);
  chassis_->setActivationState(DISABLE_DEACTIVATION);
  nameCollisions(*chassis_, chassis_names_);
  // Bullet turns the inverse inertia into world axes only here, or after a step: a world transform alone
  // left the first substep with the inertia of the chassis unrotated.
  chassis_->setCenterOfMassTransform(toBullet(root_pose * root_to_body_));
  world_.addRigidBody(chassis_.get(), kRobotGroup, kStaticGroup | kRobotGroup);

  // Each wheel's spring sags kSag under its load at rest, so that the chassis rests level (springs alike
  // under unequal loads tilted it: a caster two-wheeler rested 4 mrad nose-up and met a wall with its lower
  // edge first); critically damped. The loads are weighed in the world's gravity at spawn, or in Earth's
  // where that is weaker: a tyre does not soften on the Moon, and a weightless world (Gazebo takes one) would
  // leave no spring at all.
  const Eigen::Vector3d com = root_to_body_.translation();
  std::vector<Eigen::Vector2d> wheels;
  for (const Wheel& wheel : wheels_) {
    const Eigen::Vector3d hub = link_in_root_[joints_[wheel.joint].child_link].translation() - com;
    wheels.emplace_back(hub.x(), hub.y());
  }
  const double gravity = std::max<double>(world_.getGravity().length(), kStandardGravity);
  for (const double load : levelLoads(wheels, mass_ * gravity)) {
    springs_.push_back(load / kSag);
    dampers_.push_back(2 * kDampingRatio * std::sqrt(springs_.back() * load / gravity));
  }
  spring_frequency_ = std::sqrt(gravity / kSag);
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

void RaycastRobot::addWheelRims(btCompoundShape& compound) {
  for (size_t w = 0; w < wheels_.size(); ++w) {
    const Wheel& wheel = wheels_[w];
    const Joint& joint = joints_[wheel.joint];
    const Collision& collision = spec_.links[joint.child_link].collisions.front();
    Shape rim = collision.shape;
    rim.radius -= kRimInset;
    rim_children_.push_back(compound.getNumChildShapes());
    compound.addChildShape(toBullet(body_to_root_ * link_in_root_[joint.child_link] * collision.origin),
                           shapes_->make(rim, true));
    chassis_sources_.push_back({spec_.links[joint.child_link].name, 0});
  }
}

void RaycastRobot::updateHubs() {
  if (!hubs_stale_) return;
  const auto& frames = linkFrames();
  auto& compound = static_cast<btCompoundShape&>(*chassis_->getCollisionShape());
  for (size_t w = 0; w < wheels_.size(); ++w) {
    const int link = joints_[wheels_[w].joint].child_link;
    if (hub_in_root_[w].isApprox(frames[link], 1e-12)) continue;
    hub_in_root_[w] = frames[link];
    // The rim follows kinematic joints (steering); a wheel's spin leaves its cylinder where it is.
    const Eigen::Isometry3d origin = spec_.links[link].collisions.front().origin;
    compound.updateChildTransform(rim_children_[w], toBullet(body_to_root_ * hub_in_root_[w] * origin),
                                  false);
  }
  compound.recalculateLocalAabb();
  hubs_stale_ = false;
}

bool RaycastRobot::tune(btManifoldPoint& point, int child, bool ours_is_a, bool joining) const {
  const auto rim = std::find(rim_children_.begin(), rim_children_.end(), child);
  if (rim == rim_children_.end()) return false;
  const size_t w = static_cast<size_t>(rim - rim_children_.begin());
  const Wheel& wheel = wheels_[w];
  // A free wheel's spin yields to what it meets (its rim's friction stops it): ordinary friction.
  if (wheel.max_torque <= 0) return false;
  const Joint& joint = joints_[wheel.joint];
  const Eigen::Isometry3d root = rootPose();
  const Eigen::Isometry3d hub = root * hub_in_root_[w];
  const Eigen::Vector3d axis = hub.linear() * joint.spec->axis;
  const Eigen::Vector3d normal = (ours_is_a ? 1.0 : -1.0) * fromBullet(point.m_normalWorldOnB);  // towards us
  const Eigen::Vector3d rolling = axis.cross(normal);
  if (rolling.norm() < kRollingNormMin) return false;  // the wheel's flat side: ordinary friction
  const Eigen::Vector3d on_us =
      fromBullet(ours_is_a ? point.getPositionWorldOnA() : point.getPositionWorldOnB());
  // The rim's surface moves at spin x (point - hub) against the chassis; friction holds it to the other body.
  // Bullet's friction aims at A's velocity less B's along each direction: our surface's motion, signed.
  const Eigen::Vector3d surface =
      (ours_is_a ? -1.0 : 1.0) * (axis * joint.velocity).cross(on_us - hub.translation());
  if (joining) {
    point.m_contactMotion1 += surface.dot(fromBullet(point.m_lateralFrictionDir1));
    point.m_contactMotion2 += surface.dot(fromBullet(point.m_lateralFrictionDir2));
  } else {
    const Eigen::Vector3d direction = rolling.normalized();
    point.m_lateralFrictionDir1 = toBullet(direction);
    point.m_lateralFrictionDir2 = toBullet(normal.cross(direction));
    point.m_contactMotion1 = direction.dot(surface);
    point.m_contactMotion2 = 0;
    point.m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
  }
  // The motor turns the rim against this friction: it carries at most its torque over the radius. The rim's
  // normal impulse this substep is estimated from the last solve's, plus what stopping the chassis's approach
  // at this point takes (a strike's first contact). Bullet has one coefficient for both directions, so a rim
  // whose motor cannot hold the friction also slides along a wall more easily (and a coasting robot's, its
  // motors at 1e-9 N m, meets walls without friction).
  const Eigen::Vector3d com = fromBullet(chassis_->getWorldTransform().getOrigin());
  const Eigen::Vector3d velocity = fromBullet(chassis_->getLinearVelocity()) +
                                   fromBullet(chassis_->getAngularVelocity()).cross(on_us - com);
  const double approach = std::max(0.0, -velocity.dot(normal));
  const double pressed = rim_normal_impulse_[w] + mass_ * approach;
  const double most = wheel.max_torque * dt_ / wheel.radius;  // [N s] the motor's rim impulse this substep
  // The point's friction is the lesser mu of the rim and what it meets, or the other rim's grip (joining).
  if (point.m_combinedFriction * pressed > most) point.m_combinedFriction = most / pressed;
  return true;
}

void RaycastRobot::weigh(const btManifoldPoint& point, int child) {
  const auto rim = std::find(rim_children_.begin(), rim_children_.end(), child);
  if (rim != rim_children_.end()) rim_impulse_weighed_[rim - rim_children_.begin()] += point.m_appliedImpulse;
}

void RaycastRobot::beforeSubstep(double substep) {
  dt_ = substep;
  for (auto& joint : joints_) {
    if (joint.wheel < 0 && joint.velocity != 0) {  // kinematic joints move at their velocity
      joint.position += joint.velocity * dt_;
      hubs_stale_ = frames_stale_ = true;
    }
  }
  followLeaders();
  updateHubs();
  rim_normal_impulse_.swap(rim_impulse_weighed_);  // what the last solve weighed; the next one sums afresh
  std::fill(rim_impulse_weighed_.begin(), rim_impulse_weighed_.end(), 0.0);
  const Eigen::Isometry3d root = rootPose();
  castWheelRays(root);
  const btMatrix3x3& inverse_inertia = chassis_->getInvInertiaTensorWorld();
  for (int r = 0; r < 3; ++r) inverse_inertia_.row(r) = fromBullet(inverse_inertia[r]);
  // What plugins push with acts through the whole step, one substep at a time.
  chassis_->applyCentralImpulse(toBullet(step_force_ * dt_));
  chassis_->applyTorqueImpulse(toBullet(step_torque_ * dt_));
  for (const auto& wheel : wheels_) {  // efforts (ros_control's, the world API's) spin the wheels too
    Joint& joint = joints_[wheel.joint];
    joint.velocity = damped(wheel, joint.velocity + joint.external_effort * dt_ / wheel.inertia);
  }
  // The suspension, the motors and friction together: sequential impulses over the wheels, with each spring
  // solved implicitly, each motor's impulse held within torque * dt and each contact's within the friction
  // circle.
  pressWheels(root);
  linear_velocity_ = fromBullet(chassis_->getLinearVelocity());  // the passes work on a copy, kept in Eigen
  angular_velocity_ = fromBullet(chassis_->getAngularVelocity());
  warmStart();
  for (int pass = 0; pass < kIterations; ++pass) {
    double largest = 0;  // [N s] the largest change of any impulse in this pass
    for (size_t w = 0; w < wheels_.size(); ++w) largest = std::max({largest, supportWheel(w), driveWheel(w)});
    if (largest < kConvergedImpulse) break;
  }
  chassis_->setLinearVelocity(toBullet(linear_velocity_));
  chassis_->setAngularVelocity(toBullet(angular_velocity_));
  for (size_t w = 0; w < wheels_.size(); ++w) {
    Joint& joint = joints_[wheels_[w].joint];
    joint.effort = contacts_[w].motor_impulse / dt_ + joint.external_effort;
    joint.position += joint.velocity * dt_;
  }
}

SubstepLimit RaycastRobot::substepLimit() const {
  // The springs' own frequency, kept from the spawn: a later change of gravity does not change them.
  // Asked of every moving model at each spawn: no stream for the reason.
  return {1 / (kSubstepsPerRadian * spring_frequency_),
          "the raycast suspension's " + std::to_string(std::lround(spring_frequency_)) + " rad/s"};
}

double RaycastRobot::elasticEnergy() const {
  double energy = 0;
  for (size_t w = 0; w < contacts_.size(); ++w)
    energy += 0.5 * springs_[w] * contacts_[w].compression * contacts_[w].compression;
  return energy;
}

double RaycastRobot::damped(const Wheel& wheel, double spin) const {
  return spin * (1 - std::min(joints_[wheel.joint].spec->damping * dt_ * wheel.inverse_inertia, 1.0));
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
  ground_.castStatic(ray_origins_, ray_directions_, reach, ray_hits_, &ray_normals_, &ray_frictions_);
}

RaycastRobot::Row RaycastRobot::row(const Eigen::Vector3d& offset, const Eigen::Vector3d& direction) const {
  Row row;
  row.direction = direction;
  row.arm = offset.cross(direction);
  row.turn = inverse_inertia_ * row.arm;
  row.shift = direction / mass_;
  row.inverse_mass = 1 / mass_ + row.arm.dot(row.turn);
  return row;
}

inline double RaycastRobot::velocityAlong(const Row& row) const {
  return linear_velocity_.dot(row.direction) + angular_velocity_.dot(row.arm);
}

inline void RaycastRobot::push(const Row& row, double impulse) {
  linear_velocity_ += row.shift * impulse;
  angular_velocity_ += row.turn * impulse;
}

void RaycastRobot::pressWheels(const Eigen::Isometry3d& root) {
  const Eigen::Vector3d up = root.linear().col(2);
  const Eigen::Vector3d com = fromBullet(chassis_->getWorldTransform().getOrigin());
  gravity_speed_ = fromBullet(world_.getGravity()).dot(up) * dt_;
  // The implicit spring-damper (Catto's soft constraint): over the substep, the wheel's impulse lambda leaves
  // it separating at bias - softness * lambda, where the spring's compression x gives bias = k x / (h k + c)
  // and softness = 1 / (h (h k + c)).
  for (size_t w = 0; w < wheels_.size(); ++w) {
    const double stiffness = dt_ * springs_[w] + dampers_[w];
    Wheel& wheel = wheels_[w];
    Contact& contact = contacts_[w];
    const Contact last = contact;
    contact = Contact{};
    const double budget = std::max(wheel.max_torque, 0.0) * dt_;
    contact.motor_impulse = std::clamp(last.motor_impulse, -budget, budget);
    const double compression = wheel.radius - ray_hits_[w];
    if (!(compression > 0)) continue;  // in the air (a miss is +inf)
    if (ray_normals_[w].dot(up) < std::cos(kSteepestGround)) continue;  // a wall carries no wheel
    const Eigen::Vector3d offset = ray_origins_[w] - up * ray_hits_[w] - com;
    contact.compression = compression;
    contact.bias = springs_[w] * compression / stiffness;
    contact.softness = 1 / (dt_ * stiffness);
    contact.on_ground = true;
    contact.normal = row(offset, up);
    contact.soft_mass = 1 / (contact.normal.inverse_mass + contact.softness);
    contact.normal_mass = 1 / contact.normal.inverse_mass;
    if (last.on_ground) contact.normal_impulse = last.normal_impulse;
    contact.grips = !wheel.caster;
    if (!contact.grips) continue;
    contact.friction = std::min(wheel.friction, ray_frictions_[w]);
    if (last.grips) {
      contact.forward_impulse = last.forward_impulse;
      contact.lateral_impulse = last.lateral_impulse;
    }
    const Eigen::Vector3d axis = root.linear() * (hub_in_root_[w].linear() * joints_[wheel.joint].spec->axis);
    const Eigen::Vector3d forward = axis.cross(up).normalized();  // where a positive spin rolls the wheel
    contact.forward = row(offset, forward);
    contact.lateral = row(offset, up.cross(forward));
    // One mass for both directions: with a mass each, the clamped impulse would settle along M * slip, not
    // against the slip, and skid steering would turn off Coulomb's rate (issue 29). The smaller one is
    // stable. A rim its motor holds passes the whole forward impulse to the chassis; a slipping one also
    // spins.
    const double lateral_mass = 1 / contact.lateral.inverse_mass;
    contact.grip_mass_held = std::min(1 / contact.forward.inverse_mass, lateral_mass);
    contact.grip_mass_free =
        std::min(1 / (contact.forward.inverse_mass + wheel.radius * wheel.radius * wheel.inverse_inertia),
                 lateral_mass);
  }
}

void RaycastRobot::warmStart() {
  for (size_t w = 0; w < wheels_.size(); ++w) {
    const Contact& contact = contacts_[w];
    const Wheel& wheel = wheels_[w];
    // The motor turns the wheel; the rim's forward friction turns it back.
    joints_[wheel.joint].velocity +=
        (contact.motor_impulse - wheel.radius * contact.forward_impulse) * wheel.inverse_inertia;
    if (contact.on_ground) push(contact.normal, contact.normal_impulse);
    if (!contact.grips) continue;
    push(contact.forward, contact.forward_impulse);
    push(contact.lateral, contact.lateral_impulse);
  }
}

double RaycastRobot::supportWheel(size_t w) {
  Contact& contact = contacts_[w];
  if (!contact.on_ground) return 0;
  // How fast the wheel separates from the ground at the substep's end, gravity included (Bullet adds it
  // next).
  const double separating = velocityAlong(contact.normal) + gravity_speed_;
  const double wanted =
      contact.normal_impulse +
      (contact.bias - separating - contact.softness * contact.normal_impulse) * contact.soft_mass;
  // Never pulling, and never pushing the chassis off faster than kMaxSeparatingSpeed: at most the impulse
  // that leaves it separating at that speed, less than the one it has when it separates faster (a warm
  // start's).
  const double most = contact.normal_impulse + (kMaxSeparatingSpeed - separating) * contact.normal_mass;
  const double total = std::clamp(wanted, 0.0, std::max(most, 0.0));
  push(contact.normal, total - contact.normal_impulse);
  const double change = std::abs(total - contact.normal_impulse);
  contact.normal_impulse = total;
  return change;
}

double RaycastRobot::driveWheel(size_t w) {
  Contact& contact = contacts_[w];
  Wheel& wheel = wheels_[w];
  Joint& joint = joints_[wheel.joint];
  const double budget = wheel.max_torque * dt_;
  double motor_change = 0;
  if (wheel.max_torque > 0) {
    const double wanted = contact.motor_impulse + (wheel.spin_target - joint.velocity) * wheel.inertia;
    const double total = std::clamp(wanted, -budget, budget);
    motor_change = std::abs(total - contact.motor_impulse);
    joint.velocity += (total - contact.motor_impulse) * wheel.inverse_inertia;
    contact.motor_impulse = total;
  }
  if (!contact.grips) return motor_change;
  // Slip of the chassis over the rim, and the impulses that would cancel it (the rim shares the forward one).
  const double forward_slip = velocityAlong(contact.forward) - joint.velocity * wheel.radius;
  const double lateral_slip = velocityAlong(contact.lateral);
  // While its motor has torque to spare, the motor holds the rim: the chassis takes the whole impulse.
  const bool held = wheel.max_torque > 0 && std::abs(contact.motor_impulse) < budget;
  const double mass = held ? contact.grip_mass_held : contact.grip_mass_free;
  Eigen::Vector2d total(contact.forward_impulse - forward_slip * mass,
                        contact.lateral_impulse - lateral_slip * mass);
  const double limit = contact.friction * contact.normal_impulse;  // the friction circle
  const double size = total.norm();
  if (size > limit) total *= limit / size;
  const Eigen::Vector2d change = total - Eigen::Vector2d(contact.forward_impulse, contact.lateral_impulse);
  contact.forward_impulse = total.x();
  contact.lateral_impulse = total.y();
  push(contact.forward, change.x());
  push(contact.lateral, change.y());
  // The rim feels the reaction; a holding motor takes what it can, the rest turns the wheel.
  const double reaction = wheel.radius * change.x();
  const double motor =
      held ? std::clamp(contact.motor_impulse + reaction, -budget, budget) : contact.motor_impulse;
  joint.velocity -= (reaction - (motor - contact.motor_impulse)) * wheel.inverse_inertia;
  contact.motor_impulse = motor;
  return std::max({motor_change, std::abs(change.x()), std::abs(change.y())});
}

void RaycastRobot::followLeaders() {
  for (auto& joint : joints_) {
    if (joint.leader < 0 || joint.wheel >= 0) continue;  // a wheel's spin is dynamic: it follows nothing
    const JointSpec::Mimic& mimic = *joint.spec->mimic;
    const Joint& leader = joints_[joint.leader];
    const double position = std::clamp(mimic.multiplier * leader.position + mimic.offset, joint.spec->lower,
                                       joint.spec->upper);
    if (position != joint.position) hubs_stale_ = frames_stale_ = true;
    joint.position = position;
    joint.velocity = mimic.multiplier * leader.velocity;
  }
}

void RaycastRobot::afterStep() {
  step_force_.setZero();
  step_torque_.setZero();
  for (auto& joint : joints_) joint.external_effort = 0;
  refreshPose();
}

void RaycastRobot::refreshPose() {
  frames_stale_ = true;  // the wheels turned
  root_pose_ = rootPose();
}

void RaycastRobot::reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) {
  for (auto& joint : joints_) joint.position = joint.velocity = joint.effort = joint.external_effort = 0;
  for (const auto& [joint, position] : joints) joints_.at(joint).position = position;
  // Gazebo's joint friction is its motor's force limit at rest (ODE's fmax, with vel 0), until a drive sets
  // the motor.
  for (auto& wheel : wheels_) {
    wheel.spin_target = 0;
    wheel.max_torque = joints_[wheel.joint].spec->friction;
  }
  hubs_stale_ = frames_stale_ = true;
  wakeTouching(world_, {chassis_.get()});  // what rests on it falls
  chassis_->setCenterOfMassTransform(toBullet(root_pose * root_to_body_));
  chassis_->setLinearVelocity(btVector3(0, 0, 0));
  chassis_->setAngularVelocity(btVector3(0, 0, 0));
  chassis_->clearForces();
  for (auto& contact : contacts_) contact = Contact{};
  std::fill(rim_normal_impulse_.begin(), rim_normal_impulse_.end(), 0.0);
  std::fill(rim_impulse_weighed_.begin(), rim_impulse_weighed_.end(), 0.0);
  afterStep();
}

void RaycastRobot::teleport(const Eigen::Isometry3d& root_pose) {
  wakeTouching(world_, {chassis_.get()});  // what rests on it falls
  chassis_->setCenterOfMassTransform(toBullet(root_pose * root_to_body_));
  refreshPose();
}

void RaycastRobot::setJointPositions(const JointPositions& joints) {
  for (const auto& [joint, position] : joints) {
    joints_.at(joint).position = position;
    joints_.at(joint).velocity = 0;
  }
  hubs_stale_ = frames_stale_ = true;
}

void RaycastRobot::setStepSize(double step_size) {
  if (step_size != dt_) {  // impulses scale with the substep: the next one starts afresh
    for (auto& contact : contacts_) contact = Contact{};
  }
  dt_ = step_size;
}

int RaycastRobot::jointIndex(const std::string& joint) const {
  const auto found = joint_index_.find(joint);
  return found == joint_index_.end() ? -1 : found->second;
}

void RaycastRobot::setJointVelocity(int joint, double velocity, double max_effort) {
  Joint& target = joints_.at(joint);
  if (target.wheel >= 0) {
    wheels_[target.wheel].spin_target = velocity;
    wheels_[target.wheel].max_torque = max_effort;
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
  target.external_effort += effort;  // on top of a motor another plugin set, as Gazebo's SetForce
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
  step_force_ += force;
  step_torque_ += torque + (linkPose(link).translation() - com).cross(force);
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
  return linkPoseAt(found->second);
}

Eigen::Isometry3d RaycastRobot::linkPoseAt(int link) const {
  // A link fixed to the root (its base_link, a lidar's mount) keeps the frame the constructor found.
  const auto& frames = fixed_to_root_[link] ? link_in_root_ : linkFrames();
  return root_pose_ * frames[link];
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

Eigen::Isometry3d RaycastRobot::partPose(int part) const { return linkPoseAt(part_root_links_.at(part)); }

std::vector<CollisionContact> RaycastRobot::contacts(const CollisionSource& source) const {
  const auto found = std::find(chassis_sources_.begin(), chassis_sources_.end(), source);
  if (found == chassis_sources_.end()) return {};  // a wheel: its ray is its contact
  return contactsOf(world_, *chassis_, static_cast<int>(found - chassis_sources_.begin()), dt_);
}

}  // namespace bullet_sim
