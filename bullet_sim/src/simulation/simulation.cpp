#include "bullet_sim/simulation/simulation.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "bullet_sim/common/request_values.h"
#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/model/sdf_model.h"
#include "physics/multibody_robot.h"
#include "physics/raycast_robot.h"
#include "physics/rigid_body_model.h"
#include "common/work_pool.h"

namespace bullet_sim {

namespace {

/// A model of the `contact` wheel model, or one without wheels: one rigid body when nothing in it moves
/// (its contacts cost less to solve), a multibody otherwise.
std::unique_ptr<PhysicsRobot> makeContactBody(ModelSpec model, const std::string& name,
                                              btMultiBodyDynamicsWorld& world,
                                              const Eigen::Isometry3d& root) {
  if (isOneRigidBody(model)) return std::make_unique<RigidBodyModel>(std::move(model), name, world, root);
  return std::make_unique<MultiBodyRobot>(std::move(model), name, world, root);
}

Eigen::Isometry3d rootPose(const ModelSpec& model, const SpawnPose& pose) {
  Eigen::Isometry3d root = Eigen::Isometry3d::Identity();
  root.translate(Eigen::Vector3d(pose.x, pose.y, 0));
  root.rotate(Eigen::AngleAxisd(pose.yaw, Eigen::Vector3d::UnitZ()) *
              Eigen::AngleAxisd(pose.pitch, Eigen::Vector3d::UnitY()) *
              Eigen::AngleAxisd(pose.roll, Eigen::Vector3d::UnitX()));
  if (pose.z || (hasFixedBase(model) && !model.is_static)) {  // fixed to the world where it is put
    root.translation().z() = pose.z.value_or(0.0);
    return root;
  }
  double lowest = std::numeric_limits<double>::infinity();
  const auto links = linkPosesAtZero(model);
  for (const auto& link : model.links) {
    for (const auto& collision : link.collisions) {
      lowest = std::min(lowest, lowestPoint(collision.shape, root * links.at(link.name) * collision.origin));
    }
  }
  if (std::isfinite(lowest)) root.translation().z() = -lowest;
  return root;
}

/// The same primitive of the same size within 1 mm, or the same mesh file at the same scale.
bool sameShape(const Shape& a, const Shape& b) {
  constexpr double kTolerance = 0.001;  // [m] saved worlds round sizes (Gazebo writes 6 significant digits)
  if (a.type != b.type) return false;
  switch (a.type) {
    case Shape::Type::kBox:
      return (a.box_size - b.box_size).cwiseAbs().maxCoeff() < kTolerance;
    case Shape::Type::kCylinder:
      return std::abs(a.radius - b.radius) < kTolerance && std::abs(a.length - b.length) < kTolerance;
    case Shape::Type::kSphere:
      return std::abs(a.radius - b.radius) < kTolerance;
    case Shape::Type::kMesh:  // a saved world names it model://..., the URDF package://...
      return std::filesystem::path(a.mesh_path).filename() == std::filesystem::path(b.mesh_path).filename() &&
             a.mesh_scale.isApprox(b.mesh_scale);
    case Shape::Type::kPlane:
      return false;
  }
  return false;
}

/// Whether `world_model` is a saved copy of `model` in the way of its spawn at `root`: it has exactly the
/// robot's collision shapes, matched one to one (Gazebo saves each URDF collision as one SDF collision, at
/// whatever joint angles it had), and its bounding box overlaps the robot's.
bool isCopyInTheWay(const WorldModelSpec& world_model, const ModelSpec& model,
                    const Eigen::Isometry3d& root) {
  std::vector<const Shape*> unmatched;
  Eigen::AlignedBox3d robot_box;
  const auto links = linkPosesAtZero(model);
  for (const auto& link : model.links) {
    for (const auto& collision : link.collisions) {
      unmatched.push_back(&collision.shape);
      robot_box.extend(boundingBox(collision.shape, root * links.at(link.name) * collision.origin));
    }
  }
  if (unmatched.empty() || unmatched.size() != world_model.collisions.size()) return false;
  Eigen::AlignedBox3d copy_box;
  for (const auto& collision : world_model.collisions) {
    const auto match = std::find_if(unmatched.begin(), unmatched.end(),
                                    [&](const Shape* shape) { return sameShape(*shape, collision.shape); });
    if (match == unmatched.end()) return false;
    unmatched.erase(match);
    copy_box.extend(boundingBox(collision.shape, world_model.pose * collision.origin));
  }
  return robot_box.intersects(copy_box);
}

/// Every number of a spawn pose finite, and its position within max_length of the origin.
void checkSpawnPose(const SpawnPose& pose, const Limits& limits, Diagnostics& diagnostics) {
  const std::pair<const char*, double> lengths[] = {{"x", pose.x}, {"y", pose.y}, {"z", pose.z.value_or(0)}};
  for (const auto& [name, value] : lengths) {
    if (auto problem = boundProblem(value, limits.max_length, "max_length", "m"))
      diagnostics.error(std::string("spawn pose ") + name + " " + *problem);
  }
  const std::pair<const char*, double> angles[] = {
      {"roll", pose.roll}, {"pitch", pose.pitch}, {"yaw", pose.yaw}};
  for (const auto& [name, value] : angles) {
    if (!std::isfinite(value))
      diagnostics.error(std::string("spawn pose ") + name + " [" + std::to_string(value) +
                        "] is not a finite number");
  }
}

/// A warning when physics cannot cut its steps as finely as robot `name`'s `limit` asks (it cuts a step into
/// at most a thousand substeps): the robot then steps slowly, and less accurately than it needs. "" if none.
std::string substepShortfall(const std::string& name, const SubstepLimit& limit,
                             const PhysicsWorld& physics) {
  if (!(physics.substep() > limit.seconds * (1 + 1e-9))) return "";
  std::ostringstream warning;
  warning.precision(3);
  warning << "robot [" << name << "]: " << limit.reason << " allows substeps of " << limit.seconds * 1e3
          << " ms, but physics cuts a step into at most " << physics.substeps() << " ("
          << physics.substep() * 1e3
          << " ms): it runs slowly, and less accurately than it needs (a heavier light link, or less joint "
             "damping, allows longer substeps)";
  return warning.str();
}

/// The wheel-ground model of a robot named `name`: contact for a static one; else what its plugins ask for
/// (its drive's, ros_control's rule), else contact.
std::string wheelModelOf(const ModelSpec& model, const std::string& name, const SpawnPose& pose,
                         const SimulationOptions& options, Diagnostics& diagnostics) {
  if (hasFixedBase(model)) return "contact";
  const WheelModelQuery query{model, name, pose.robot_namespace, options.parameters, diagnostics};
  return options.plugins->wheelModel(query).value_or("contact");
}

}  // namespace

SpawnPose spawnPoseFrom(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation,
                        bool place_on_ground, Diagnostics& diagnostics) {
  SpawnPose spawn;
  if (!position.allFinite()) {
    std::ostringstream message;
    message << "spawn position [" << position.transpose() << "] is not finite";
    diagnostics.error(message.str());
    return spawn;
  }
  Eigen::Matrix3d rotation;
  try {
    const Eigen::Vector4d& q = orientation.coeffs();
    rotation = requireRotation(q.x(), q.y(), q.z(), q.w(), "spawn orientation").toRotationMatrix();
  } catch (const std::invalid_argument& e) {
    diagnostics.error(e.what());
    return spawn;
  }
  if (orientation.coeffs().isZero(0))
    diagnostics.warning("spawn orientation (x y z w) [0 0 0 0] is no rotation: the identity is used");
  spawn.x = position.x();
  spawn.y = position.y();
  spawn.yaw = std::atan2(rotation(1, 0), rotation(0, 0));
  spawn.pitch = std::asin(-std::clamp(rotation(2, 0), -1.0, 1.0));
  spawn.roll = std::atan2(rotation(2, 1), rotation(2, 2));
  if (!place_on_ground) spawn.z = position.z();
  return spawn;
}

Robot::Robot(std::string name, std::unique_ptr<PhysicsRobot> body, const Eigen::Isometry3d& spawn_pose)
    : name_(std::move(name)), body_(std::move(body)), spawn_pose_(spawn_pose) {}

Robot::~Robot() = default;

Simulation::Simulation(WorldSpec world, SimulationOptions options)
    : world_(std::move(world)),
      options_(options),
      pool_(std::make_unique<WorkPool>(options_.threads > 0 ? options_.threads : defaultPoolThreads())),
      lane_(options_.lockstep ? nullptr : std::make_unique<WorkLane>()) {
  physics_ = std::make_unique<PhysicsWorld>(world_, options_.physics);
  physics_->shareSolvesWith(pool_.get());
  for (const auto& model : world_.models) {
    PlacedWorldModel& placed = world_models_.emplace_back();
    placed.pose = model.pose;
    if (!model.is_static) {
      makeWorldBody(model, placed);
    } else if (!model.collisions.empty()) {
      placed.ray_body = rays_.addBody(model.collisions, model.pose, true);
    }
  }
  rays_.commit();
  fitSubsteps();
  if (options_.images) images_ = options_.images(*this);
}

Simulation::~Simulation() = default;

void Simulation::makeWorldBody(const WorldModelSpec& model, PlacedWorldModel& placed) {
  Diagnostics diagnostics(world_.source);
  ModelSpec spec =
      toModelSpec(model, *options_.plugins, diagnostics, options_.limits, /*weld_unjoined=*/true);
  decomposer_.attach(spec, options_.limits, diagnostics);
  diagnostics.throwIfErrors();
  const Eigen::Isometry3d root = model.pose * spec.root_in_model;
  auto body = makeContactBody(std::move(spec), model.name, physics_->bullet(), root);
  placed.body = std::make_unique<Robot>(model.name, std::move(body), root);
  Robot& robot = *placed.body;
  addRayBodies(robot);
  placed.visual_link.assign(model.visuals.size(), 0);
  for (size_t l = 0; l < model.links.size(); ++l) {
    placed.link_to_model.push_back(robot.body().linkPose(model.links[l].name).inverse() * model.pose);
    for (size_t visual : model.links[l].visual_indices) placed.visual_link.at(visual) = l;
  }
}

std::vector<Robot*> Simulation::movingModels() {
  std::vector<Robot*> moving;
  for (auto& placed : world_models_) {
    if (placed.body) moving.push_back(placed.body.get());
  }
  for (auto& robot : robots_) moving.push_back(robot.get());
  return moving;
}

Eigen::Isometry3d Simulation::worldModelPose(size_t model) const {
  const PlacedWorldModel& placed = world_models_.at(model);
  if (!placed.body) return placed.pose;
  const RobotBody& body = placed.body->body();
  return body.linkPose(body.spec().root) * body.spec().root_in_model.inverse();
}

Eigen::Isometry3d Simulation::worldVisualFrame(size_t model, size_t visual) const {
  const PlacedWorldModel& placed = world_models_.at(model);
  if (!placed.body || placed.link_to_model.empty()) return worldModelPose(model);
  const size_t link = placed.visual_link.at(visual);
  return placed.body->body().linkPose(world_.models[model].links[link].name) * placed.link_to_model[link];
}

void Simulation::moveWorldModel(size_t model, const Eigen::Isometry3d& pose) {
  finishCasts();
  PlacedWorldModel& placed = world_models_.at(model);
  placed.pose = pose;
  physics_->setModelPose(model, pose);
  if (placed.ray_body != kNoBody) {
    // Static bodies share one tree, so a moved one is taken out and put back in.
    rays_.removeBody(placed.ray_body);
    placed.ray_body = rays_.addBody(world_.models[model].collisions, pose, /*is_static=*/true);
    rays_.commit();
  }
}

Robot* Simulation::worldBody(size_t model) { return world_models_.at(model).body.get(); }

Robot& Simulation::spawn(const std::string& name, ModelSpec model, const SpawnPose& pose,
                         std::vector<std::string>* warnings) {
  Diagnostics diagnostics(model.source);
  if (name.empty()) diagnostics.error("a robot needs a name");
  if (robot(name))
    diagnostics.error("a robot named [" + name + "] already exists: delete it first, or choose another name");
  checkSpawnPose(pose, options_.limits, diagnostics);
  diagnostics.throwIfErrors();
  const Eigen::Isometry3d root = rootPose(model, pose);
  for (const auto& world_model : world_.models) {
    if (world_model.name == name) {
      diagnostics.error("the world already holds a model named [" + name +
                        "]: was the world saved with the robot in it? Remove it from the .world file");
    } else if (isCopyInTheWay(world_model, model, root)) {
      diagnostics.error("the world's model [" + world_model.name + "] has the collision shapes of robot [" +
                        name + "] where it spawns: was the world saved with the robot in it? Remove [" +
                        world_model.name + "] from the .world file, or spawn the robot elsewhere");
    }
  }
  const std::string wheel_model = wheelModelOf(model, name, pose, options_, diagnostics);
  diagnostics.throwIfErrors();
  finishCasts();  // the robot's parts join the ray caster
  if (model.is_static) {  // a static model is rigid: its joints do not move
    for (auto& joint : model.joints) joint.type = JointSpec::Type::kFixed;
  }
  decomposer_.attach(model, options_.limits, diagnostics);
  std::unique_ptr<PhysicsRobot> body;
  if (wheel_model == "raycast") {
    body = std::make_unique<RaycastRobot>(std::move(model), name, physics_->bullet(), rays_, root);
  } else {
    body = makeContactBody(std::move(model), name, physics_->bullet(), root);
  }
  auto robot = std::make_unique<Robot>(name, std::move(body), root);
  robot->wheel_model_ = wheel_model;
  for (const auto& [joint, position] : pose.joints) {
    const int index = robot->body().jointIndex(joint);
    if (index < 0) {
      diagnostics.error("initial position for [" + joint + "], which is not a moving joint" +
                        didYouMean(joint, robot->body().spec().jointNames()));
    } else if (auto problem = boundProblem(position, options_.limits.max_length, "max_length", "")) {
      diagnostics.error("initial position for [" + joint + "] " + *problem);
    } else {
      robot->spawn_joints_.emplace_back(index, position);
    }
  }
  diagnostics.throwIfErrors();
  robot->body().reset(root, robot->spawn_joints_);
  equip(*robot, pose.robot_namespace, diagnostics);
  if (warnings)
    warnings->insert(warnings->end(), diagnostics.warnings().begin(), diagnostics.warnings().end());
  robots_.push_back(std::move(robot));
  fitSubsteps();
  if (warnings) {
    const std::string shortfall = substepShortfall(name, robots_.back()->body_->substepLimit(), *physics_);
    if (!shortfall.empty()) warnings->push_back(shortfall);
  }
  return *robots_.back();
}

void Simulation::fitSubsteps() {
  double longest = std::numeric_limits<double>::infinity();
  for (Robot* model : movingModels()) longest = std::min(longest, model->body_->substepLimit().seconds);
  physics_->setLongestSubstep(longest);
  for (Robot* model : movingModels()) model->body_->setStepSize(physics_->substep());
}

std::string Simulation::substepNote(const std::string& name) const {
  const Robot* found = robot(name);
  if (!found) throw std::invalid_argument("no robot [" + name + "]");
  std::ostringstream note;
  note.precision(3);
  note << "physics substep " << physics_->substep() * 1e3 << " ms (" << physics_->substeps() << " per "
       << stepSize() * 1e3 << " ms step)";
  const SubstepLimit limit = found->body_->substepLimit();
  if (!limit.reason.empty()) note << "; " << limit.reason << " allows " << limit.seconds * 1e3 << " ms";
  return note.str();
}

void Simulation::addRayBodies(Robot& robot) {
  const auto& parts = robot.body().parts();
  for (size_t k = 0; k < parts.size(); ++k) {
    robot.ray_bodies_.push_back(parts[k].collisions.empty()
                                    ? kNoBody
                                    : rays_.addBody(parts[k].collisions, robot.body().partPose(k), false));
  }
}

void Simulation::equip(Robot& robot, const std::optional<std::string>& robot_namespace,
                       Diagnostics& diagnostics) {
  addRayBodies(robot);
  try {
    for (const auto& declaration : robot.body().spec().plugins) {
      const PluginType* type = options_.plugins->typeOf(declaration);
      const unsigned needs = type ? type->needs : 0;
      PluginSetup setup{robot.body(), robot.name()};
      setup.seed = options_.seed;
      setup.robot_namespace = robot_namespace;
      setup.diagnostics = &diagnostics;
      if (type) setup.tf_prefix = type->tf_prefix;
      if (needs & kNeedGravity) setup.gravity = physics_->gravity();
      if (needs & kNeedOwnRayBody) {
        const int part = declaration.sensor ? robot.body().partOf(declaration.sensor->link) : -1;
        if (part >= 0) setup.own_ray_body = robot.ray_bodies_[part];
      }
      if (needs & kNeedImages) setup.images = images_.get();
      if (needs & kNeedGeodesy) setup.spherical_coordinates = world_.spherical_coordinates;
      if (needs & kNeedParameters) setup.parameters = options_.parameters;
      robot.plugins_.push_back(options_.plugins->create(declaration, setup));
    }
  } catch (const std::exception& e) {
    diagnostics.error(e.what());
  }
  if (!diagnostics.errors().empty()) {
    for (BodyId body : robot.ray_bodies_) {
      if (body != kNoBody) rays_.removeBody(body);
    }
  }
  rays_.commit();
  diagnostics.throwIfErrors();
}

bool Simulation::remove(const std::string& name) {
  const auto found =
      std::find_if(robots_.begin(), robots_.end(), [&](const auto& r) { return r->name() == name; });
  if (found == robots_.end()) return false;
  finishCasts();
  for (BodyId body : (*found)->ray_bodies_) {
    if (body != kNoBody) rays_.removeBody(body);
  }
  rays_.commit();
  robots_.erase(found);
  physics_->releaseMemory();
  for (StepHooks* hooks : hooks_) hooks->robotRemoved(name);
  fitSubsteps();
  return true;
}

Robot* Simulation::robot(const std::string& name) {
  for (auto& robot : robots_) {
    if (robot->name() == name) return robot.get();
  }
  return nullptr;
}

const Robot* Simulation::robot(const std::string& name) const {
  for (const auto& robot : robots_) {
    if (robot->name() == name) return robot.get();
  }
  return nullptr;
}

std::vector<std::string> Simulation::robotNames() const {
  std::vector<std::string> names;
  for (const auto& robot : robots_) names.push_back(robot->name());
  return names;
}

void Simulation::step() {
  const StepTime time{timeAfter(steps_ + 1), options_.physics.step_size};
  deliverCastsDue(time);
  for (StepHooks* hooks : hooks_) hooks->beforeStep();
  ray_casting_.clear();
  for (auto& robot : robots_) {
    bool casts = false;
    for (size_t k = 0; k < robot->plugins_.size(); ++k) {
      robot->plugins_[k]->applyCommands(time, *robot->body_);
      casts |= !robot->casting(k) && robot->plugins_[k]->castsRays(time);  // not while its last cast runs
    }
    if (casts) ray_casting_.push_back(robot.get());
  }
  const std::vector<Robot*> moving = movingModels();
  // On the stepping thread: shared with the pool, a hundred wheelchairs took a tenth more CPU time and ran no
  // faster, the pool's thread taking the core the lane casts scans on (performance.md).
  physics_->step([&](double substep) {
    for (Robot* model : moving) model->body_->beforeSubstep(substep);
  });
  for (Robot* model : moving) model->body_->afterStep();
  if (!ray_casting_.empty()) castRays(time);
  sense(time);
  ++steps_;
  // A scan delivered since the last step ended may not have been read yet: the next ones wait for a step.
  if (lane_ && !delivered_since_step_) deliverCasts(finishedCasts());
  delivered_since_step_ = false;
}

double Simulation::aimRays(const StepTime& time) {
  double next_due = std::numeric_limits<double>::infinity();
  for (Robot* robot : ray_casting_) {
    robot->casting_.resize(robot->plugins_.size());
    for (size_t k = 0; k < robot->plugins_.size(); ++k) {
      Plugin& plugin = *robot->plugins_[k];
      robot->casting_[k] = plugin.castsRays(time);
      if (!robot->casting_[k]) continue;
      plugin.aimRays(time, *robot->body_);
      next_due = std::min(next_due, plugin.nextUpdateAfter(time));
    }
  }
  return next_due;
}

void Simulation::castEach(const Robot& robot, RayCaster& rays) {
  for (size_t k = 0; k < robot.plugins_.size(); ++k) {
    if (robot.casting_[k]) robot.plugins_[k]->castRays(rays);
  }
}

void Simulation::castRays(const StepTime& time) {
  if (lane_) return castBehind(time);
  aimRays(time);
  refreshRays();  // once, for every scan due in this step
  std::exception_ptr failure;
  try {
    pool_->run(ray_casting_.size(), [&](size_t k) { castEach(*ray_casting_[k], rays_); });
  } catch (...) {
    failure = std::current_exception();
  }
  for (Robot* robot : ray_casting_) robot->casting_.clear();  // all of them sense in this step
  if (failure) std::rethrow_exception(failure);
}

void Simulation::sense(const StepTime& time) {
  for (auto& robot : robots_) {
    for (size_t k = 0; k < robot->plugins_.size(); ++k) {
      if (!robot->casting(k)) robot->plugins_[k]->sense(time, *robot->body_, rays_);
    }
  }
}

void Simulation::castBehind(const StepTime& time) {
  // A robot casts in one batch at a time: one whose other plugin's rays are still on the lane senses first.
  const auto in_flight = [](const Robot* robot) { return !robot->casting_.empty(); };
  if (std::any_of(ray_casting_.begin(), ray_casting_.end(), in_flight)) finishCasts();
  const double next_due = aimRays(time);
  std::vector<std::pair<BodyId, Eigen::Isometry3d>> poses;
  rayBodyPoses(poses);
  // The lane moves its bodies once the casts before have met them where they were, beside the raycast wheels
  // (which meet only static bodies).
  const uint64_t ticket = lane_->start([this, robots = ray_casting_, poses = std::move(poses)] {
    moveRayBodies(poses);
    for (const Robot* robot : robots) castEach(*robot, rays_);
  });
  casts_behind_.push_back({ray_casting_, time, next_due, ticket});
}

void Simulation::deliverCasts(size_t count) {
  if (count == 0) return;
  std::exception_ptr failure;
  try {
    lane_->wait(casts_behind_[count - 1].ticket);
  } catch (...) {
    failure = std::current_exception();
  }
  for (size_t i = 0; i < count; ++i) {
    const CastBehind& cast = casts_behind_.front();
    for (Robot* robot : cast.robots) {
      for (size_t k = 0; k < robot->plugins_.size() && !failure; ++k) {
        if (robot->casting_[k]) robot->plugins_[k]->sense(cast.time, *robot->body_, rays_);
      }
      robot->casting_.clear();
    }
    casts_behind_.pop_front();
  }
  delivered_since_step_ = true;
  if (failure) std::rethrow_exception(failure);
}

size_t Simulation::finishedCasts() const {
  size_t count = 0;
  while (count < casts_behind_.size() && lane_->finished(casts_behind_[count].ticket)) ++count;
  return count;
}

void Simulation::deliverCastsDue(const StepTime& time) {
  size_t count = 0;
  for (size_t i = 0; i < casts_behind_.size(); ++i) {
    if (time.sim_time >= casts_behind_[i].next_due - time.dt / 2) count = i + 1;
  }
  deliverCasts(count);
}

void Simulation::finishCasts() { deliverCasts(casts_behind_.size()); }

void Simulation::refreshRays() {
  finishCasts();
  rayBodyPoses(ray_poses_);
  moveRayBodies(ray_poses_);
}

void Simulation::rayBodyPoses(std::vector<std::pair<BodyId, Eigen::Isometry3d>>& poses) {
  poses.clear();
  for (Robot* robot : movingModels()) {
    for (size_t k = 0; k < robot->ray_bodies_.size(); ++k) {
      if (robot->ray_bodies_[k] != kNoBody)
        poses.emplace_back(robot->ray_bodies_[k], robot->body_->partPose(k));
    }
  }
}

void Simulation::moveRayBodies(const std::vector<std::pair<BodyId, Eigen::Isometry3d>>& poses) {
  for (const auto& [body, pose] : poses) rays_.setPose(body, pose);
  rays_.commit();
}

void Simulation::resetWorld() {
  finishCasts();
  for (size_t i = 0; i < world_models_.size(); ++i) {
    const Eigen::Isometry3d& in_file = world_.models[i].pose;
    if (Robot* body = world_models_[i].body.get()) {
      body->body_->reset(body->spawn_pose_, {});
    } else if (world_models_[i].pose.matrix() != in_file.matrix()) {
      moveWorldModel(i, in_file);
    }
  }
  for (auto& robot : robots_) {
    robot->body_->reset(robot->spawn_pose_, robot->spawn_joints_);
    for (auto& plugin : robot->plugins_) plugin->reset();
  }
  physics_->forgetContacts();
  refreshRays();
}

void Simulation::resetSimulation() {
  resetWorld();
  steps_ = steps_at_base_ = 0;
  time_base_ = 0;
}

void Simulation::setStepSize(double step_size) {
  if (!(step_size > 0 && std::isfinite(step_size))) {
    std::ostringstream message;
    message << "step size [" << step_size << " s] must be positive and finite";
    throw std::invalid_argument(message.str());
  }
  time_base_ = time();
  steps_at_base_ = steps_;
  options_.physics.step_size = step_size;
  physics_->setStepSize(step_size);
  fitSubsteps();
}

StepHooks::StepHooks(Simulation& simulation) : hooked_(simulation) { hooked_.hooks_.push_back(this); }

StepHooks::~StepHooks() {
  auto& hooks = hooked_.hooks_;
  hooks.erase(std::remove(hooks.begin(), hooks.end(), this), hooks.end());
}

}  // namespace bullet_sim
