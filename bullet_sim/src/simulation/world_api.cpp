// Gazebo's world API over a simulation (world_api.h): naming entities, their states in reference frames,
// teleports, scheduled wrenches and efforts, physics properties. The semantics are those of gazebo_ros's
// api plugin (noetic), unless a comment says otherwise.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/request_values.h"
#include "bullet_sim/model/gazebo_names.h"
#include "bullet_sim/simulation/world_api.h"

namespace bullet_sim {

namespace {

constexpr double kForever = std::numeric_limits<double>::infinity();

bool isWorldFrame(const std::string& name) {
  return name.empty() || name == "world" || name == "map" || name == "/map";
}

std::string scoped(const std::string& model, const std::string& link) { return model + "::" + link; }

// What a request may ask, far beyond any robot's world: past it, Bullet and the single-precision ray caster
// lose the model (Embree aborts on a ray cast from infinity). Positions and offsets are bounded by
// limits().max_length, as spawn poses and descriptions are. Every component is checked: a norm lets a NaN
// or an overflow past.
constexpr double kMaxSpeed = 1e6;         // [m/s], [rad/s]
constexpr double kMaxLoad = 1e12;         // [N], [N m]: a force, a torque, an effort
constexpr double kMaxAcceleration = 1e6;  // [m/s^2] of gravity
constexpr double kMinStep = 1e-6;         // [s]: below it, Bullet's impulses (divided by the step) overflow
constexpr double kMaxStep = 1.0;          // [s]
// [steps per wall s], unless 0 (as fast as possible): one step in 1000 s. Slower, the node's wait for the
// next step leaves the range of a ROS duration.
constexpr double kMinUpdateRate = 1e-3;

std::string number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

/// Throws naming `field` (and its component) unless each component is finite and within limits.max_length.
void checkPosition(const Eigen::Vector3d& position, const Limits& limits, const std::string& field) {
  for (int i = 0; i < 3; ++i) {
    if (auto problem = boundProblem(position[i], limits.max_length, "max_length", "m"))
      throw std::invalid_argument(field + "." + "xyz"[i] + " " + *problem);
  }
}

/// Throws naming the field of a state requested for `what` (gazebo_msgs' names) that cannot be simulated.
void checkState(const EntityState& state, const std::string& what, const Limits& limits) {
  if (!state.pose.linear().allFinite())
    throw std::invalid_argument(what + ": pose.orientation is not finite");
  checkPosition(state.pose.translation(), limits, what + ": pose.position");
  requireWithin(state.linear, kMaxSpeed, what + ": twist.linear", "m/s");
  requireWithin(state.angular, kMaxSpeed, what + ": twist.angular", "rad/s");
}

/// Throws naming `what` unless a wrench's or an effort's window is made of numbers.
void checkSchedule(const Schedule& schedule, const std::string& what) {
  requireFinite(schedule.start_time, what + ": start_time");
  if (std::isnan(schedule.duration)) throw std::invalid_argument(what + ": duration [nan] is not a number");
}

/// A world state seen from a frame whose world state is `frame`, as Gazebo computes it: the frame's
/// velocities are subtracted, then turned into its axes.
EntityState relativeTo(const EntityState& state, const EntityState& frame) {
  const Eigen::Matrix3d to_frame = frame.pose.linear().transpose();
  return {frame.pose.inverse() * state.pose, to_frame * (state.linear - frame.linear),
          to_frame * (state.angular - frame.angular)};
}

/// A state given in a frame whose world state is `frame`, in the world, as Gazebo takes it: the pose
/// composed, the twist turned into world axes.
EntityState inWorld(const EntityState& state, const EntityState& frame) {
  return {frame.pose * state.pose, frame.pose.linear() * state.linear, frame.pose.linear() * state.angular};
}

/// Drops the elements of `items` that `drop` selects (std::erase_if of C++20).
template <class Item, class Predicate>
void eraseIf(std::vector<Item>& items, Predicate drop) {
  items.erase(std::remove_if(items.begin(), items.end(), drop), items.end());
}

/// The end of a window that starts at `start` [s]: a duration shorter than a step lasts one step.
double windowEnd(const Schedule& schedule, double start, double step) {
  return schedule.duration < 0 ? kForever : start + std::max(schedule.duration, step);
}

}  // namespace

WorldApi::WorldApi(Simulation& simulation, double max_update_rate)
    : StepHooks(simulation), simulation_(simulation), max_update_rate_(max_update_rate) {}

std::vector<std::string> WorldApi::modelNames() const {
  std::vector<std::string> names;
  for (const auto& model : simulation_.world().models) names.push_back(model.name);
  for (const std::string& robot : simulation_.robotNames()) names.push_back(robot);
  return names;
}

WorldApi::Entity WorldApi::findModel(const std::string& name) const {
  const std::vector<WorldModelSpec>& world_models = simulation_.world().models;
  for (size_t i = 0; i < world_models.size(); ++i) {
    if (world_models[i].name == name) return {simulation_.worldBody(i), static_cast<int>(i), ""};
  }
  if (Robot* robot = simulation_.robot(name)) return {robot, -1, ""};
  throw std::invalid_argument("no model [" + name + "]" + didYouMean(name, modelNames()));
}

WorldApi::Entity WorldApi::findEntity(const std::string& name, const std::string& what) const {
  // Gazebo looks a name up as a model, then as a scoped link, then as any model's link of that bare name.
  std::vector<std::string> known;
  for (const std::string& model_name : modelNames()) {
    const Entity model = findModel(model_name);
    if (model_name == name) return model;
    std::vector<std::string> links;
    if (model.robot) {
      links = model.robot->body().spec().linkNames();
    } else {
      for (const auto& link : simulation_.world().models[model.world_model].links) {
        links.push_back(link.name);
      }
    }
    for (const std::string& link : links) {
      if (scoped(model_name, link) == name) return {model.robot, model.world_model, link};
      known.push_back(scoped(model_name, link));
    }
  }
  for (const std::string& candidate : known) {
    const auto split = candidate.find("::");
    if (candidate.substr(split + 2) == name) return findEntity(candidate, what);
  }
  const std::vector<std::string> models = modelNames();
  known.insert(known.end(), models.begin(), models.end());
  throw std::invalid_argument(what + " [" + name + "] names no model or link" + didYouMean(name, known) +
                              "; name a link as model::link");
}

WorldApi::Entity WorldApi::findLink(const std::string& name) const {
  Entity entity = findEntity(name, "link");
  if (entity.link.empty()) {
    throw std::invalid_argument("[" + name + "] is a model, not a link: name one of its links as [" + name +
                                "::LINK]");
  }
  return entity;
}

std::pair<Robot*, std::string> WorldApi::findBody(const std::string& name) const {
  const Entity entity = findEntity(name, "body");
  if (entity.robot && entity.robot->body().spec().is_static) {
    throw std::invalid_argument("body [" + name + "] belongs to static model [" + entity.robot->name() +
                                "]: it takes no wrench");
  }
  if (!entity.robot) {
    throw std::invalid_argument("body [" + name + "] belongs to the world's static model [" +
                                simulation_.world().models[entity.world_model].name +
                                "]: it takes no wrench");
  }
  return {entity.robot, entity.link.empty() ? entity.robot->body().spec().root : entity.link};
}

std::vector<Robot*> WorldApi::modelsWithJoints() const {
  std::vector<Robot*> models;
  for (size_t i = 0; i < simulation_.world().models.size(); ++i) {
    if (Robot* body = simulation_.worldBody(i)) models.push_back(body);
  }
  for (const std::string& robot : simulation_.robotNames()) models.push_back(simulation_.robot(robot));
  return models;
}

std::pair<Robot*, int> WorldApi::findJoint(const std::string& name) const {
  const std::vector<Robot*> models = modelsWithJoints();
  std::vector<std::string> known;
  for (Robot* robot : models) {
    for (const JointSpec& joint : robot->body().spec().joints) {
      if (!joint.moves()) continue;
      if (joint.name == name || scoped(robot->name(), joint.name) == name) {
        return {robot, robot->body().jointIndex(joint.name)};
      }
      known.push_back(scoped(robot->name(), joint.name));
    }
  }
  for (Robot* robot : models) {
    const std::string prefix = robot->name() + "::";
    const bool scoped_here = name.rfind(prefix, 0) == 0;
    if (robot->body().spec().joint(scoped_here ? name.substr(prefix.size()) : name)) {
      throw std::invalid_argument("joint [" + name + "] is fixed: bullet_sim merges the links it joins, as " +
                                  "Gazebo lumps them, so it has no state");
    }
  }
  throw std::invalid_argument("no moving joint [" + name + "]" + didYouMean(name, known));
}

EntityState WorldApi::worldState(const Entity& entity) const {
  if (!entity.robot) {
    EntityState state;
    state.pose = simulation_.worldModelPose(entity.world_model);
    if (!entity.link.empty()) {
      for (const auto& link : simulation_.world().models[entity.world_model].links) {
        if (link.name == entity.link) state.pose = state.pose * link.pose;
      }
    }
    return state;
  }
  const RobotBody& body = entity.robot->body();
  const std::string& link = entity.link.empty() ? body.spec().root : entity.link;
  // A model's pose is its frame's; its velocities are its root link's, as Gazebo takes its canonical link's.
  const Eigen::Isometry3d frame =
      entity.link.empty() ? body.spec().root_in_model.inverse() : Eigen::Isometry3d::Identity();
  return {body.linkPose(link) * frame, body.linkLinearVelocity(link), body.linkAngularVelocity(link)};
}

EntityState WorldApi::entityState(const std::string& entity) const {
  return isWorldFrame(entity) ? EntityState{} : worldState(findEntity(entity, "reference frame"));
}

std::vector<NamedState> WorldApi::modelStates() const {
  std::vector<NamedState> states;
  for (const std::string& name : modelNames()) states.push_back({name, worldState(findModel(name))});
  return states;
}

std::vector<NamedState> WorldApi::linkStates() const {
  std::vector<NamedState> states;
  const std::vector<WorldModelSpec>& world_models = simulation_.world().models;
  for (size_t i = 0; i < world_models.size(); ++i) {
    for (const auto& link : world_models[i].links) {
      states.push_back({scoped(world_models[i].name, link.name),
                        worldState({simulation_.worldBody(i), static_cast<int>(i), link.name})});
    }
  }
  for (const std::string& name : simulation_.robotNames()) {
    Robot* robot = simulation_.robot(name);
    for (const RobotPart& part : robot->body().parts()) {
      states.push_back({scoped(name, part.root_link), worldState({robot, -1, part.root_link})});
    }
  }
  return states;
}

EntityState WorldApi::modelState(const std::string& model, const std::string& reference) const {
  const EntityState state = worldState(findModel(model));
  return isWorldFrame(reference) ? state : relativeTo(state, entityState(reference));
}

EntityState WorldApi::linkState(const std::string& link, const std::string& reference) const {
  const EntityState state = worldState(findLink(link));
  return isWorldFrame(reference) ? state : relativeTo(state, entityState(reference));
}

std::string WorldApi::setModelState(const std::string& model, const EntityState& state,
                                      const std::string& reference) {
  const Entity entity = findModel(model);
  checkState(state, "model [" + model + "]", simulation_.limits());
  const EntityState target = inWorld(state, entityState(reference));
  checkState(target, "model [" + model + "] in the world", simulation_.limits());
  return setWorldState(entity, target);
}

std::string WorldApi::setLinkState(const std::string& link, const EntityState& state,
                                     const std::string& reference) {
  const Entity entity = findLink(link);
  checkState(state, "link [" + link + "]", simulation_.limits());
  const EntityState target = inWorld(state, entityState(reference));
  checkState(target, "link [" + link + "] in the world", simulation_.limits());
  if (!entity.robot) {
    const Entity model{nullptr, entity.world_model, ""};
    const Eigen::Isometry3d in_model = worldState(model).pose.inverse() * worldState(entity).pose;
    return setWorldState(model, {target.pose * in_model.inverse(), target.linear, target.angular});
  }
  const RobotBody& body = entity.robot->body();
  if (body.partOf(entity.link) != 0) {
    const JointSpec* joint = body.spec().parentJoint(entity.link);
    while (joint && !joint->moves()) joint = body.spec().parentJoint(joint->parent);
    throw std::invalid_argument(
        "link [" + link + "] moves on joint [" + (joint ? joint->name : "") +
        "]: set_link_state moves a robot only by the links rigidly fixed to its root; "
        "set its joints with set_model_configuration");
  }
  // The root goes where it must for the link to be at the target, moving with the link's twist.
  const Eigen::Isometry3d link_in_root =
      body.linkPose(body.spec().root).inverse() * body.linkPose(entity.link);
  const Eigen::Isometry3d root = target.pose * link_in_root.inverse();
  const Eigen::Vector3d linear =
      target.linear + target.angular.cross(root.translation() - target.pose.translation());
  return setWorldState({entity.robot, -1, ""}, {root, linear, target.angular});
}

std::string WorldApi::setWorldState(const Entity& model, const EntityState& state) {
  const bool still = state.linear.isZero() && state.angular.isZero();
  if (model.robot) {
    PhysicsRobot& body = model.robot->body();
    body.teleport(state.pose * body.spec().root_in_model);
    body.setRootVelocity(state.linear, state.angular);
    simulation_.refreshRays();
    if (still || !body.spec().is_static) return "";
    return "model [" + model.robot->name() +
           "] is static: it moved, but it does not move by itself, so its "
           "twist is ignored";
  }
  simulation_.moveWorldModel(model.world_model, state.pose);
  if (still) return "";
  return "the world's model [" + simulation_.world().models[model.world_model].name +
         "] is static geometry in bullet_sim: it moved, but it does not move by itself, so its twist is "
         "ignored";
}

ModelProperties WorldApi::modelProperties(const std::string& model) const {
  const Entity entity = findModel(model);
  ModelProperties properties;
  if (entity.world_model >= 0) {  // named as its file names them
    const WorldModelSpec& spec = simulation_.world().models[entity.world_model];
    properties.is_static = spec.is_static;
    for (const auto& joint : spec.joints) properties.joint_names.push_back(joint.name);
    std::set<std::string> children;
    for (const auto& link : spec.links) {
      properties.body_names.push_back(link.name);
      properties.geom_names.insert(properties.geom_names.end(), link.collisions.begin(),
                                   link.collisions.end());
      if (const auto nested = link.name.find("::"); nested != std::string::npos) {
        if (children.insert(link.name.substr(0, nested)).second) {
          properties.child_model_names.push_back(link.name.substr(0, nested));
        }
      }
    }
    return properties;
  }
  const RobotBody& body = entity.robot->body();
  for (const RobotPart& part : body.parts()) properties.body_names.push_back(part.root_link);
  for (const GazeboCollision& collision : gazeboCollisions(body.spec())) {
    properties.geom_names.push_back(collision.name);
  }
  for (const JointSpec& joint : body.spec().joints) {
    if (joint.moves()) properties.joint_names.push_back(joint.name);
  }
  properties.is_static = body.spec().is_static;
  return properties;
}

LinkProperties WorldApi::linkProperties(const std::string& link) const {
  const Entity entity = findLink(link);
  if (!entity.robot) {
    throw std::invalid_argument("link [" + link + "] belongs to the world's static model [" +
                                simulation_.world().models[entity.world_model].name +
                                "], which bullet_sim keeps as static geometry, without mass");
  }
  const LinkSpec& spec = *entity.robot->body().spec().link(entity.link);
  LinkProperties properties;
  properties.gravity = spec.gravity;
  if (spec.inertial) {
    properties.mass = spec.inertial->mass;
    properties.com = spec.inertial->com;
    properties.inertia = spec.inertial->inertia;
  }
  return properties;
}

JointProperties WorldApi::jointProperties(const std::string& joint) const {
  const auto [robot, index] = findJoint(joint);
  const RobotBody& body = robot->body();
  const std::string bare = joint.substr(joint.rfind("::") == std::string::npos ? 0 : joint.rfind("::") + 2);
  const JointSpec& spec = *body.spec().joint(bare);
  return {spec.type, body.jointPosition(index), body.jointVelocity(index), spec.damping, spec.lower,
          spec.upper};
}

std::string WorldApi::setModelConfiguration(const std::string& model,
                                              const std::map<std::string, double>& positions) {
  const Entity entity = findModel(model);
  if (!entity.robot) {
    throw std::invalid_argument("model [" + model + "] is the world's: bullet_sim keeps its joints rigid");
  }
  PhysicsRobot& body = entity.robot->body();
  std::string problems, skipped;
  JointPositions joints;
  for (const auto& [joint, position] : positions) {
    const int index = body.jointIndex(joint);
    if (index < 0) {
      skipped += "; [" + joint + "] is not a moving joint of [" + model + "]" +
                 didYouMean(joint, body.spec().jointNames());
    } else if (auto problem = boundProblem(position, simulation_.limits().max_length, "max_length", "")) {
      problems += "; the position of [" + joint + "] " + *problem;
    } else {
      joints.emplace_back(index, position);
    }
  }
  if (!problems.empty()) throw std::invalid_argument(problems.substr(2));
  body.setJointPositions(joints);
  simulation_.refreshRays();
  std::string note = skipped.empty() ? "" : "skipped, as Gazebo skips them: " + skipped.substr(2);
  for (const auto& plugin : entity.robot->plugins()) {
    for (const std::string& warning : plugin->jointsPlaced(body))
      note += (note.empty() ? "" : "; ") + warning;
  }
  return note;
}

void WorldApi::driveJoint(const std::string& joint, double velocity, double max_effort) {
  requireWithin(velocity, kMaxSpeed, "joint [" + joint + "]: vel", "rad/s or m/s");
  requireWithin(max_effort, kMaxLoad, "joint [" + joint + "]: fmax", "N m or N");
  if (max_effort < 0)
    throw std::invalid_argument("joint [" + joint + "]: fmax [" + number(max_effort) + "] must be >= 0");
  const auto [robot, index] = findJoint(joint);
  robot->body().setJointVelocity(index, velocity, max_effort);
}

std::string WorldApi::applyBodyWrench(const BodyWrench& wrench) {
  const std::string on = "the wrench on [" + wrench.body + "]";
  requireWithin(wrench.force, kMaxLoad, on + ": wrench.force", "N");
  requireWithin(wrench.torque, kMaxLoad, on + ": wrench.torque", "N m");
  checkPosition(wrench.reference_point, simulation_.limits(), on + ": reference_point");
  checkSchedule(wrench.schedule, on);
  const auto [robot, link] = findBody(wrench.body);
  const Eigen::Matrix3d axes = entityState(wrench.reference_frame).pose.linear();
  if (wrench.schedule.duration == 0) return "duration 0: nothing is applied, as gazebo_msgs documents";
  const Eigen::Vector3d force = axes * wrench.force;
  const double start = std::max(wrench.schedule.start_time, simulation_.time());
  wrenches_.push_back({robot->name(), link, force,
                       axes * wrench.torque + (axes * wrench.reference_point).cross(force), start,
                       windowEnd(wrench.schedule, start, simulation_.stepSize())});
  return "";
}

void WorldApi::clearBodyWrenches(const std::string& body) {
  const auto [robot, link] = findBody(body);
  eraseIf(wrenches_, [&, robot = robot, link = link](const ScheduledWrench& wrench) {
    return wrench.robot == robot->name() && wrench.link == link;
  });
}

std::string WorldApi::applyJointEffort(const JointEffort& effort) {
  const std::string on = "the effort on joint [" + effort.joint + "]";
  requireWithin(effort.effort, kMaxLoad, on + ": effort", "N m or N");
  checkSchedule(effort.schedule, on);
  const auto [robot, index] = findJoint(effort.joint);
  if (!robot->body().takesJointEffort(index)) {
    throw std::invalid_argument("joint [" + effort.joint + "] of robot [" + robot->name() +
                                "] is moved kinematically by the raycast wheel model, which applies no "
                                "effort to it: give the robot's drive <wheelModel>contact</wheelModel>");
  }
  if (effort.schedule.duration == 0) return "duration 0: nothing is applied, as gazebo_msgs documents";
  const double start = std::max(effort.schedule.start_time, simulation_.time());
  const double end = windowEnd(effort.schedule, start, simulation_.stepSize());
  efforts_.push_back({robot->name(), index, effort.effort, start, end});
  if (effort.schedule.duration > 0 && effort.schedule.duration < simulation_.stepSize()) {
    return "duration below the step size: applied for one step";
  }
  return "";
}

void WorldApi::clearJointEfforts(const std::string& joint) {
  const auto [robot, index] = findJoint(joint);
  eraseIf(efforts_, [&, robot = robot, index = index](const ScheduledEffort& effort) {
    return effort.robot == robot->name() && effort.joint == index;
  });
}

void WorldApi::beforeStep() {
  if (wrenches_.empty() && efforts_.empty()) return;  // the usual step
  // A window holds the steps that start in [start, end); half a step absorbs rounding in the times.
  const double now = simulation_.time() + simulation_.stepSize() / 2;
  eraseIf(wrenches_, [&](const ScheduledWrench& wrench) { return now >= wrench.end; });
  eraseIf(efforts_, [&](const ScheduledEffort& effort) { return now >= effort.end; });
  for (const ScheduledWrench& wrench : wrenches_) {
    if (now < wrench.start) continue;
    PhysicsRobot& body = findModel(wrench.robot).robot->body();  // a robot or a world's body
    const LinkSpec& link = *body.spec().link(wrench.link);
    const Eigen::Isometry3d pose = body.linkPose(wrench.link);
    const Eigen::Vector3d com = link.inertial ? pose * link.inertial->com : pose.translation();
    body.applyLinkWrench(wrench.link, wrench.force,
                         wrench.torque + (com - pose.translation()).cross(wrench.force));
  }
  for (const ScheduledEffort& effort : efforts_) {
    if (now < effort.start) continue;
    findModel(effort.robot).robot->body().applyJointEffort(effort.joint, effort.effort);
  }
}

void WorldApi::robotRemoved(const std::string& name) {
  eraseIf(wrenches_, [&](const ScheduledWrench& wrench) { return wrench.robot == name; });
  eraseIf(efforts_, [&](const ScheduledEffort& effort) { return effort.robot == name; });
}

PhysicsProperties WorldApi::physicsProperties() const {
  return {simulation_.stepSize(), max_update_rate_, simulation_.physics().gravity()};
}

void WorldApi::setPhysicsProperties(const PhysicsProperties& properties) {
  requireFinite(properties.step_size, "time_step");
  if (!(properties.step_size > 0)) {
    throw std::invalid_argument("time_step [" + number(properties.step_size) + "] must be positive");
  }
  if (properties.step_size < kMinStep) {
    throw std::invalid_argument("time_step [" + number(properties.step_size) + " s] is below the " +
                                number(kMinStep) + " s bullet_sim steps by");
  }
  requireWithin(properties.step_size, kMaxStep, "time_step", "s");
  requireFinite(properties.max_update_rate, "max_update_rate");
  const double rate = properties.max_update_rate;
  if (rate < 0 || (rate > 0 && rate < kMinUpdateRate)) {
    throw std::invalid_argument("max_update_rate [" + number(rate) +
                                "] must be 0 (as fast as possible) or at least " + number(kMinUpdateRate) +
                                " steps per second");
  }
  requireWithin(properties.gravity, kMaxAcceleration, "gravity", "m/s^2");
  if (properties.step_size != simulation_.stepSize()) simulation_.setStepSize(properties.step_size);
  max_update_rate_ = properties.max_update_rate;
  simulation_.physics().setGravity(properties.gravity);
}

}  // namespace bullet_sim
