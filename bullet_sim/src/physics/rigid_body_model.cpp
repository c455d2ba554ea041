#include "physics/rigid_body_model.h"

#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "bullet_shapes.h"
#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/gazebo_names.h"
#include "bullet_sim/model/model_geometry.h"
#include "physics/multibody_robot.h"
#include "physics/robot_parts.h"
#include "physics/sleep.h"

namespace bullet_sim {

bool isOneRigidBody(const ModelSpec& model) {
  const auto moves = [](const JointSpec& joint) { return joint.moves(); };
  const auto weightless = [](const LinkSpec& link) { return !link.gravity && link.inertial; };
  return !hasFixedBase(model) && std::none_of(model.joints.begin(), model.joints.end(), moves) &&
         std::none_of(model.links.begin(), model.links.end(), weightless);
}

RigidBodyModel::RigidBodyModel(ModelSpec model, std::string name, btMultiBodyDynamicsWorld& world,
                               const Eigen::Isometry3d& root_pose)
    : spec_(std::move(model)),
      name_(std::move(name)),
      world_(world),
      dt_(world.getSolverInfo().m_timeStep),
      shapes_(std::make_unique<BulletShapes>()) {
  PartLayout layout = partitionAtMovingJoints(spec_);
  if (layout.parts.size() != 1) throw std::logic_error("model [" + spec_.name + "] is not one rigid body");
  parts_ = std::move(layout.parts);
  link_in_part_ = std::move(layout.link_in_part.front());
  buildBody(root_pose);
  reset(root_pose, {});
}

RigidBodyModel::~RigidBodyModel() {
  wakeTouching(world_, {body_.get()});  // what rests on it falls; its contacts go with it
  world_.removeRigidBody(body_.get());
}

void RigidBodyModel::buildBody(const Eigen::Isometry3d& root_pose) {
  Diagnostics diagnostics(spec_.source);
  const RobotPart& part = parts_.front();
  std::vector<std::pair<std::string, Eigen::Isometry3d>> placed;
  for (const auto& link : part.links) placed.emplace_back(link, link_in_part_.at(link));
  const MassProperties mass = combineInertia(spec_, placed);
  checkMovingPart(part, mass.mass, diagnostics);
  diagnostics.throwIfErrors();
  Eigen::Vector3d moments;
  part_to_body_ = mass.principalFrame(&moments);

  const Eigen::Isometry3d body_to_part = part_to_body_.inverse();
  btCompoundShape* compound = shapes_->makeCompound(toBullet(body_to_part));  // bounds along the part's root
  const CollisionNames names = robotCollisionNames(name_, spec_, gazeboCollisions(spec_), part.sources);
  for (size_t c = 0; c < part.collisions.size(); ++c) {  // a mesh's convex parts are children of their own
    const Collision& collision = part.collisions[c];
    const int first = compound->getNumChildShapes();
    const int count =
        shapes_->addTo(*compound, toBullet(body_to_part * collision.origin), collision.shape, true);
    child_ranges_.emplace_back(first, count);
    collision_names_.append(names, c, count);
  }
  compound->recalculateLocalAabb();
  btRigidBody::btRigidBodyConstructionInfo info(mass.mass, nullptr, compound, toBullet(moments));
  const SurfaceSpec& surface = spec_.link(part.root_link)->surface;
  info.m_friction = surface.mu1;
  info.m_restitution = 0;
  body_ = std::make_unique<btRigidBody>(info);
  if (surface.kp || surface.kd) {  // Gazebo's defaults: a rigid contact (kp 1e12 N/m) with kd 1 N s/m
    body_->setContactStiffnessAndDamping(surface.kp.value_or(1e12), surface.kd.value_or(1.0));
  }
  if (maySleep(spec_)) {
    body_->setSleepingThresholds(kSleepSpeed, kSleepSpeed);  // the time is Bullet's gDeactivationTime
  } else {
    body_->setActivationState(DISABLE_DEACTIVATION);
  }
  nameCollisions(*body_, collision_names_);
  body_->setCenterOfMassTransform(toBullet(root_pose * part_to_body_));
  world_.addRigidBody(body_.get(), kRobotGroup, kStaticGroup | kRobotGroup);
}

void RigidBodyModel::beforeSubstep(double) {
  if (step_force_.isZero() && step_torque_.isZero()) return;
  body_->applyCentralForce(toBullet(step_force_));
  body_->applyTorque(toBullet(step_torque_));
}

void RigidBodyModel::afterStep() {
  step_force_.setZero();
  step_torque_.setZero();
  if (sleeping()) return;  // Bullet moved none of it
  part_pose_ = fromBullet(body_->getWorldTransform()) * part_to_body_.inverse();
}

void RigidBodyModel::reset(const Eigen::Isometry3d& root_pose, const JointPositions& joints) {
  setJointPositions(joints);
  body_->setLinearVelocity(btVector3(0, 0, 0));
  body_->setAngularVelocity(btVector3(0, 0, 0));
  body_->clearForces();
  teleport(root_pose);
}

void RigidBodyModel::teleport(const Eigen::Isometry3d& root_pose) {
  wakeTouching(world_, {body_.get()});  // what rests on it falls
  body_->activate();
  // With the pose, Bullet turns the inverse inertia into world axes (a world transform alone does not).
  body_->setCenterOfMassTransform(toBullet(root_pose * part_to_body_));
  afterStep();
}

void RigidBodyModel::setJointPositions(const JointPositions& joints) {
  if (!joints.empty()) throw noJoint(joints.front().first);
}

bool RigidBodyModel::sleeping() const { return body_->getActivationState() == ISLAND_SLEEPING; }

// As Gazebo's Model::SetLinearVel and SetAngularVel: the model's origin takes `linear`.
void RigidBodyModel::setRootVelocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
  body_->activate();
  const Eigen::Vector3d origin = linkPose(spec_.root).translation();
  body_->setLinearVelocity(toBullet(linear + angular.cross(centreOfMass() - origin)));
  body_->setAngularVelocity(toBullet(angular));
}

void RigidBodyModel::applyLinkWrench(const std::string& link, const Eigen::Vector3d& force,
                                     const Eigen::Vector3d& torque) {
  // Bullet takes forces at the centre of mass: the force moved there brings its moment about it.
  const Eigen::Vector3d lever = linkPose(link).translation() - centreOfMass();
  step_force_ += force;
  step_torque_ += torque + lever.cross(force);
  body_->activate();
}

Eigen::Isometry3d RigidBodyModel::linkPose(const std::string& link) const {
  return part_pose_ * linkInPart(link);
}

Eigen::Vector3d RigidBodyModel::linkLinearVelocity(const std::string& link) const {
  const Eigen::Vector3d lever = linkPose(link).translation() - centreOfMass();
  return fromBullet(body_->getLinearVelocity()) + fromBullet(body_->getAngularVelocity()).cross(lever);
}

Eigen::Vector3d RigidBodyModel::linkAngularVelocity(const std::string& link) const {
  linkInPart(link);  // names it when it is not ours
  return fromBullet(body_->getAngularVelocity());
}

Eigen::Isometry3d RigidBodyModel::partPose(int part) const {
  if (part != 0) {
    throw std::out_of_range("model [" + spec_.name + "] has one part, not " + std::to_string(part));
  }
  return part_pose_;
}

std::vector<CollisionContact> RigidBodyModel::contacts(const CollisionSource& source) const {
  const auto& sources = parts_.front().sources;
  const auto found = std::find(sources.begin(), sources.end(), source);
  if (found == sources.end()) return {};
  const auto [first, count] = child_ranges_.at(found - sources.begin());
  return contactsOf(world_, *body_, first, count, dt_);
}

std::out_of_range RigidBodyModel::noJoint(int joint) const {
  return std::out_of_range("model [" + spec_.name + "] has no moving joint " + std::to_string(joint));
}

const Eigen::Isometry3d& RigidBodyModel::linkInPart(const std::string& link) const {
  const auto found = link_in_part_.find(link);
  if (found == link_in_part_.end()) {
    throw std::out_of_range("no link [" + link + "] in model [" + spec_.name + "]");
  }
  return found->second;
}

Eigen::Vector3d RigidBodyModel::centreOfMass() const { return part_pose_ * part_to_body_.translation(); }

}  // namespace bullet_sim
