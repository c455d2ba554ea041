#include "gazebo_services.h"

#include <ros/names.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tinyxml2.h>

#include <cmath>

#include "bullet_sim/assets/package_resolver.h"
#include "bullet_sim/common/names.h"
#include "bullet_sim/common/request_values.h"
#include "bullet_sim/model/sdf_model.h"
#include "bullet_sim/plugins/registry.h"
#include "ros_parameters.h"

namespace bullet_sim {

namespace {

// [sim Hz] Gazebo publishes every step, 1 kHz at its default step
constexpr double kDefaultStatesRate = 1000;

/// Runs `body`, which returns the status message; an exception becomes success false with its message.
template <class Response, class Body>
bool answer(Response& response, Body body) {
  try {
    response.status_message = body();
    response.success = true;
  } catch (const std::exception& e) {
    response.success = false;
    response.status_message = e.what();
  }
  return true;
}

/// As Gazebo reads a pose: the quaternion normalised, and (0, 0, 0, 0), an unset one, as no rotation. Throws
/// naming `field` when the quaternion is no rotation (request_values.h); the world API checks the position.
Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& pose, const std::string& field) {
  const geometry_msgs::Quaternion& q = pose.orientation;
  return Eigen::Translation3d(pose.position.x, pose.position.y, pose.position.z) *
         requireRotation(q.x, q.y, q.z, q.w, field + ".orientation");
}

EntityState toState(const geometry_msgs::Pose& pose, const geometry_msgs::Twist& twist) {
  EntityState state;
  state.pose = toIsometry(pose, "pose");
  tf2::fromMsg(twist.linear, state.linear);
  tf2::fromMsg(twist.angular, state.angular);
  return state;
}

void fromState(const EntityState& state, geometry_msgs::Pose& pose, geometry_msgs::Twist& twist) {
  pose = tf2::toMsg(state.pose);
  tf2::toMsg(state.linear, twist.linear);
  tf2::toMsg(state.angular, twist.angular);
}

/// Whether a requested value is the one in force, within rounding (infinite limits included; NaN never).
bool sameValue(double requested, double current) {
  if (requested == current) return true;
  return std::isfinite(current) && std::abs(requested - current) <= 1e-9 * std::max(1.0, std::abs(current));
}

/// The spawn pose that puts a model's frame exactly at `pose`.
SpawnPose spawnPoseAt(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d ypr = pose.linear().eulerAngles(2, 1, 0);  // SpawnPose turns by yaw, pitch, then roll
  SpawnPose spawn;
  spawn.x = pose.translation().x();
  spawn.y = pose.translation().y();
  spawn.z = pose.translation().z();
  spawn.yaw = ypr[0];
  spawn.pitch = ypr[1];
  spawn.roll = ypr[2];
  return spawn;
}

/// The name of the root element of an XML text, or "" when it is not XML.
std::string rootElement(const std::string& xml) {
  tinyxml2::XMLDocument document;
  if (document.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS || !document.RootElement()) return "";
  return document.RootElement()->Name();
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& line : lines) text += "\n" + line;
  return text;
}

uint8_t jointType(JointSpec::Type type) {
  switch (type) {
    case JointSpec::Type::kRevolute:
      return gazebo_msgs::GetJointProperties::Response::REVOLUTE;
    case JointSpec::Type::kContinuous:
      return gazebo_msgs::GetJointProperties::Response::CONTINUOUS;
    case JointSpec::Type::kPrismatic:
      return gazebo_msgs::GetJointProperties::Response::PRISMATIC;
    case JointSpec::Type::kFixed:
      break;
  }
  return gazebo_msgs::GetJointProperties::Response::FIXED;
}

/// The world's <physics><ode> and <max_contacts> (sdformat's defaults where it gives none), which
/// get_physics_properties reports until they are set, as Noetic's Gazebo does. Gazebo leaves
/// sor_pgs_rms_error_tol at 0.
gazebo_msgs::ODEPhysics odePhysicsOf(const OdeSettings& settings) {
  gazebo_msgs::ODEPhysics ode;
  ode.auto_disable_bodies = false;
  ode.sor_pgs_precon_iters = settings.precon_iters;
  ode.sor_pgs_iters = settings.iters;
  ode.sor_pgs_w = settings.sor;
  ode.sor_pgs_rms_error_tol = 0;
  ode.contact_surface_layer = settings.contact_surface_layer;
  ode.contact_max_correcting_vel = settings.contact_max_correcting_vel;
  ode.cfm = settings.cfm;
  ode.erp = settings.erp;
  ode.max_contacts = settings.max_contacts;
  return ode;
}

/// Logs a call that service `name` refused, as Gazebo logs the calls it refuses.
void logRefusal(const std::string& name, const std::string& why) {
  ROS_ERROR("%s refused: %s", name.c_str(), why.c_str());
}

/// Advertises `owner`'s `method` as service `name`. A call it refuses is logged as well as answered.
template <class Owner, class Request, class Response>
ros::ServiceServer serveLogged(ros::NodeHandle& node, const std::string& name, Owner* owner,
                               bool (Owner::*method)(Request&, Response&)) {
  const boost::function<bool(Request&, Response&)> callback = [=](Request& request, Response& response) {
    (owner->*method)(request, response);
    if (!response.success) logRefusal(name, response.status_message);
    return true;
  };
  return node.advertiseService<Request, Response>(name, callback);
}

/// A service that always answers success false with `why`, and logs it.
template <class Service>
ros::ServiceServer refuse(ros::NodeHandle& node, const std::string& name, const std::string& why) {
  using Request = typename Service::Request;
  using Response = typename Service::Response;
  const boost::function<bool(Request&, Response&)> callback = [name, why](Request&, Response& response) {
    response.success = false;
    response.status_message = why;
    logRefusal(name, why);
    return true;
  };
  return node.advertiseService<Request, Response>(name, callback);
}

const char* const kNoLights =
    "bullet_sim simulates no lights: the world's lights (the sun) are not loaded, and cameras draw with a "
    "fixed "
    "light";

}  // namespace

GazeboServices::GazeboServices(ros::NodeHandle private_node, Simulation& simulation, WorldApi& world,
                               SimulationHost& host)
    : node_(private_node),
      simulation_(simulation),
      world_(world),
      host_(host),
      ode_(odePhysicsOf(simulation.world().ode)) {
  const double rate = numberParam(node_, "model_states_rate", kDefaultStatesRate);
  states_period_ = rate > 0 && std::isfinite(rate) ? 1.0 / rate : 0.0;
  // Subscribers are counted as they come and go, as Gazebo does, so a step without any costs nothing.
  const auto counting = [](int& count, int change) {
    return [&count, change](const ros::SingleSubscriberPublisher&) { count += change; };
  };
  model_states_ = node_.advertise<gazebo_msgs::ModelStates>("model_states", 10, counting(model_listeners_, 1),
                                                            counting(model_listeners_, -1));
  link_states_ = node_.advertise<gazebo_msgs::LinkStates>("link_states", 10, counting(link_listeners_, 1),
                                                          counting(link_listeners_, -1));
  subscribers_.push_back(node_.subscribe("set_model_state", 10, &GazeboServices::onModelState, this));
  subscribers_.push_back(node_.subscribe("set_link_state", 10, &GazeboServices::onLinkState, this));
  advertiseServices();
}

void GazeboServices::advertiseServices() {
  const auto serve = [this](const std::string& name, auto method) {
    services_.push_back(serveLogged(node_, name, this, method));
  };
  serve("spawn_urdf_model", &GazeboServices::spawnUrdf);
  serve("spawn_sdf_model", &GazeboServices::spawnSdf);
  serve("delete_model", &GazeboServices::deleteModel);
  serve("get_model_state", &GazeboServices::getModelState);
  serve("set_model_state", &GazeboServices::setModelState);
  serve("get_link_state", &GazeboServices::getLinkState);
  serve("set_link_state", &GazeboServices::setLinkState);
  serve("get_model_properties", &GazeboServices::getModelProperties);
  serve("get_world_properties", &GazeboServices::getWorldProperties);
  serve("get_joint_properties", &GazeboServices::getJointProperties);
  serve("set_joint_properties", &GazeboServices::setJointProperties);
  serve("get_link_properties", &GazeboServices::getLinkProperties);
  serve("set_link_properties", &GazeboServices::setLinkProperties);
  serve("set_model_configuration", &GazeboServices::setModelConfiguration);
  serve("apply_body_wrench", &GazeboServices::applyBodyWrench);
  serve("apply_joint_effort", &GazeboServices::applyJointEffort);
  // Their answers have no fields: they log why they refuse themselves.
  services_.push_back(
      node_.advertiseService("clear_body_wrenches", &GazeboServices::clearBodyWrenches, this));
  services_.push_back(node_.advertiseService("clear_joint_forces", &GazeboServices::clearJointForces, this));
  serve("get_physics_properties", &GazeboServices::getPhysicsProperties);
  serve("set_physics_properties", &GazeboServices::setPhysicsProperties);
  services_.push_back(refuse<gazebo_msgs::DeleteLight>(node_, "delete_light", kNoLights));
  services_.push_back(refuse<gazebo_msgs::GetLightProperties>(node_, "get_light_properties", kNoLights));
  services_.push_back(refuse<gazebo_msgs::SetLightProperties>(node_, "set_light_properties", kNoLights));
}

void GazeboServices::afterStep() {
  if (model_listeners_ <= 0 && link_listeners_ <= 0) return;
  const double now = simulation_.time();
  if (now < states_due_ - states_period_) states_due_ = 0;  // time went back: a reset
  if (now + 0.5 * simulation_.stepSize() < states_due_) return;
  publishStates();
  states_due_ = now + states_period_;
}

void GazeboServices::publishStates() {
  if (model_listeners_ > 0) {
    gazebo_msgs::ModelStates message;
    for (const NamedState& model : world_.modelStates()) {
      message.name.push_back(model.name);
      fromState(model.state, message.pose.emplace_back(), message.twist.emplace_back());
    }
    model_states_.publish(message);
  }
  if (link_listeners_ > 0) {
    gazebo_msgs::LinkStates message;
    for (const NamedState& link : world_.linkStates()) {
      message.name.push_back(link.name);
      fromState(link.state, message.pose.emplace_back(), message.twist.emplace_back());
    }
    link_states_.publish(message);
  }
}

std::string GazeboServices::spawn(const gazebo_msgs::SpawnModel::Request& request, bool sdf_too) {
  const std::string source = "model [" + request.model_name + "]";
  // The pose first: a refusal of it costs no parsing.
  Eigen::Vector3d position;
  tf2::fromMsg(request.initial_pose.position, position);
  requireFinite(position, "SpawnModel: initial_pose.position");
  const Eigen::Isometry3d initial_pose = toIsometry(request.initial_pose, "SpawnModel: initial_pose");
  std::string why;
  if (!request.robot_namespace.empty() && !ros::names::validate(request.robot_namespace, why)) {
    throw std::invalid_argument("SpawnModel: robot_namespace [" + request.robot_namespace +
                                "] is not a ROS name: " + why);
  }
  std::vector<std::string> warnings;
  const std::string root = rootElement(request.model_xml);
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  ModelSpec model;
  if (root == "robot") {
    model = parseModel(request.model_xml, source, resolver, &warnings, simulation_.limits(),
                       flagParam(node_, "strict_models", false));
  } else if (root == "sdf" && sdf_too) {
    model = parseSdfModel(request.model_xml, source, resolver, PluginRegistry::builtin(), &warnings,
                          simulation_.limits());
  } else if (root == "sdf") {
    throw std::invalid_argument("SpawnModel: " + source +
                                " is SDF, not a URDF: spawn it with spawn_sdf_model");
  } else {
    throw std::invalid_argument("SpawnModel: " + source + " is neither a URDF (<robot>) nor SDF (<sdf>): " +
                                (root.empty() ? "it is not XML" : "its root element is <" + root + ">"));
  }
  // Gazebo places the model frame at the initial pose (composed with the model's own <pose>), taken in the
  // reference frame; the robot's root link sits in it.
  const Eigen::Isometry3d pose = world_.entityState(request.reference_frame).pose *
                                 initial_pose * model.placement * model.root_in_model;
  SpawnPose spawn = spawnPoseAt(pose);
  // As gazebo_ros puts it into every plugin's <robotNamespace>, so that they read their parameters there.
  if (!request.robot_namespace.empty()) spawn.robot_namespace = request.robot_namespace;
  host_.spawnRobot(request.model_name, std::move(model), spawn, request.robot_namespace, &warnings);
  return "SpawnModel: spawned " + source + joined(warnings);
}

bool GazeboServices::spawnUrdf(gazebo_msgs::SpawnModel::Request& request,
                         gazebo_msgs::SpawnModel::Response& response) {
  return answer(response, [&] { return spawn(request, /*sdf_too=*/false); });
}

bool GazeboServices::spawnSdf(gazebo_msgs::SpawnModel::Request& request,
                        gazebo_msgs::SpawnModel::Response& response) {
  return answer(response, [&] { return spawn(request, /*sdf_too=*/true); });
}

bool GazeboServices::deleteModel(gazebo_msgs::DeleteModel::Request& request,
                           gazebo_msgs::DeleteModel::Response& response) {
  return answer(response, [&] {
    const std::vector<std::string> models = world_.modelNames();
    if (host_.deleteRobot(request.model_name))
      return "DeleteModel: deleted model [" + request.model_name + "]";
    if (std::find(models.begin(), models.end(), request.model_name) != models.end()) {
      throw std::invalid_argument("DeleteModel: [" + request.model_name +
                                  "] is a model of the world file, which bullet_sim does not delete; move it "
                                  "away with set_model_state");
    }
    throw std::invalid_argument("DeleteModel: no model [" + request.model_name + "]" +
                                didYouMean(request.model_name, models));
  });
}

bool GazeboServices::getModelState(gazebo_msgs::GetModelState::Request& request,
                             gazebo_msgs::GetModelState::Response& response) {
  return answer(response, [&] {
    const EntityState state = world_.modelState(request.model_name, request.relative_entity_name);
    fromState(state, response.pose, response.twist);
    response.header.seq = ++state_requests_[request.model_name];
    response.header.stamp = ros::Time(simulation_.time());
    response.header.frame_id = request.relative_entity_name;
    return "GetModelState: got properties";
  });
}

bool GazeboServices::setModelState(gazebo_msgs::SetModelState::Request& request,
                             gazebo_msgs::SetModelState::Response& response) {
  return answer(response, [&] {
    const gazebo_msgs::ModelState& state = request.model_state;
    const std::string note =
        world_.setModelState(state.model_name, toState(state.pose, state.twist), state.reference_frame);
    return note.empty() ? "SetModelState: set model state done" : note;
  });
}

void GazeboServices::onModelState(const gazebo_msgs::ModelState::ConstPtr& state) {
  gazebo_msgs::SetModelState::Request request;
  gazebo_msgs::SetModelState::Response response;
  request.model_state = *state;
  setModelState(request, response);
  if (!response.success) ROS_WARN_THROTTLE(1, "set_model_state: %s", response.status_message.c_str());
}

bool GazeboServices::getLinkState(gazebo_msgs::GetLinkState::Request& request,
                            gazebo_msgs::GetLinkState::Response& response) {
  return answer(response, [&] {
    const EntityState state = world_.linkState(request.link_name, request.reference_frame);
    fromState(state, response.link_state.pose, response.link_state.twist);
    response.link_state.link_name = request.link_name;
    response.link_state.reference_frame = request.reference_frame;
    return "GetLinkState: got state";
  });
}

bool GazeboServices::setLinkState(gazebo_msgs::SetLinkState::Request& request,
                            gazebo_msgs::SetLinkState::Response& response) {
  return answer(response, [&] {
    const gazebo_msgs::LinkState& state = request.link_state;
    const std::string note =
        world_.setLinkState(state.link_name, toState(state.pose, state.twist), state.reference_frame);
    return note.empty() ? "SetLinkState: success" : note;
  });
}

void GazeboServices::onLinkState(const gazebo_msgs::LinkState::ConstPtr& state) {
  gazebo_msgs::SetLinkState::Request request;
  gazebo_msgs::SetLinkState::Response response;
  request.link_state = *state;
  setLinkState(request, response);
  if (!response.success) ROS_WARN_THROTTLE(1, "set_link_state: %s", response.status_message.c_str());
}

bool GazeboServices::getModelProperties(gazebo_msgs::GetModelProperties::Request& request,
                                  gazebo_msgs::GetModelProperties::Response& response) {
  return answer(response, [&] {
    const ModelProperties properties = world_.modelProperties(request.model_name);
    response.body_names = properties.body_names;
    response.canonical_body_name = properties.body_names.empty() ? "" : properties.body_names.front();
    response.geom_names = properties.geom_names;
    response.joint_names = properties.joint_names;
    response.child_model_names = properties.child_model_names;
    response.is_static = properties.is_static;
    return "GetModelProperties: got properties";
  });
}

bool GazeboServices::getWorldProperties(gazebo_msgs::GetWorldProperties::Request&,
                                  gazebo_msgs::GetWorldProperties::Response& response) {
  return answer(response, [&] {
    response.sim_time = simulation_.time();
    response.model_names = world_.modelNames();
    response.rendering_enabled = true;  // cameras render, headless
    return "GetWorldProperties: got properties";
  });
}

bool GazeboServices::getJointProperties(gazebo_msgs::GetJointProperties::Request& request,
                                  gazebo_msgs::GetJointProperties::Response& response) {
  return answer(response, [&] {
    const JointProperties properties = world_.jointProperties(request.joint_name);
    response.type = jointType(properties.type);
    response.damping = {properties.damping};
    response.position = {properties.position};
    response.rate = {properties.rate};
    return "GetJointProperties: got properties";
  });
}

bool GazeboServices::getLinkProperties(gazebo_msgs::GetLinkProperties::Request& request,
                                 gazebo_msgs::GetLinkProperties::Response& response) {
  return answer(response, [&] {
    const LinkProperties properties = world_.linkProperties(request.link_name);
    response.com = tf2::toMsg(Eigen::Isometry3d(Eigen::Translation3d(properties.com)));
    response.gravity_mode = properties.gravity;
    response.mass = properties.mass;
    const Eigen::Matrix3d& inertia = properties.inertia;
    response.ixx = inertia(0, 0);
    response.ixy = inertia(0, 1);
    response.ixz = inertia(0, 2);
    response.iyy = inertia(1, 1);
    response.iyz = inertia(1, 2);
    response.izz = inertia(2, 2);
    return "GetLinkProperties: got properties";
  });
}

bool GazeboServices::setLinkProperties(gazebo_msgs::SetLinkProperties::Request& request,
                                 gazebo_msgs::SetLinkProperties::Response& response) {
  return answer(response, [&] {
    const LinkProperties now = world_.linkProperties(request.link_name);
    const auto differs = [](double a, double b) { return !sameValue(a, b); };
    std::vector<std::string> changed;
    if (differs(request.mass, now.mass)) changed.push_back("mass");
    if (differs(request.com.position.x, now.com.x()) || differs(request.com.position.y, now.com.y()) ||
        differs(request.com.position.z, now.com.z())) {
      changed.push_back("centre of mass");
    }
    const Eigen::Matrix3d& inertia = now.inertia;
    if (differs(request.ixx, inertia(0, 0)) || differs(request.ixy, inertia(0, 1)) ||
        differs(request.ixz, inertia(0, 2)) || differs(request.iyy, inertia(1, 1)) ||
        differs(request.iyz, inertia(1, 2)) || differs(request.izz, inertia(2, 2))) {
      changed.push_back("inertia");
    }
    if (request.gravity_mode != now.gravity) changed.push_back("gravity_mode");
    if (changed.empty()) return std::string("SetLinkProperties: nothing to change");
    throw std::invalid_argument("SetLinkProperties: bullet_sim fixes a link's " + joinedNames(changed) +
                                " at spawn (link [" + request.link_name +
                                "]): change them in the model and spawn it again");
  });
}

bool GazeboServices::setJointProperties(gazebo_msgs::SetJointProperties::Request& request,
                                  gazebo_msgs::SetJointProperties::Response& response) {
  return answer(response, [&] {
    const gazebo_msgs::ODEJointProperties& ode = request.ode_joint_config;
    const JointProperties now = world_.jointProperties(request.joint_name);
    std::vector<std::string> refused, unused;
    const auto check = [&](const char* name, const std::vector<double>& values, const double* current) {
      if (values.empty()) return;
      if (values.size() > 1) {
        refused.push_back(std::string(name) + " has " + std::to_string(values.size()) +
                          " values, and the joint one axis");
      } else if (!current) {
        unused.push_back(name);
      } else if (!sameValue(values[0], *current)) {
        refused.push_back(std::string(name) + " is fixed at spawn");
      }
    };
    check("damping", ode.damping, &now.damping);
    check("hiStop", ode.hiStop, &now.upper);
    check("loStop", ode.loStop, &now.lower);
    for (const auto& [name, values] : {std::pair{"erp", &ode.erp},
                                       {"cfm", &ode.cfm},
                                       {"stop_erp", &ode.stop_erp},
                                       {"stop_cfm", &ode.stop_cfm},
                                       {"fudge_factor", &ode.fudge_factor}}) {
      check(name, *values, nullptr);
    }
    if (ode.vel.size() > 1 || ode.fmax.size() > 1 || ode.vel.empty() != ode.fmax.empty()) {
      refused.push_back("vel and fmax drive the joint's motor together, one value each");
    }
    if (!refused.empty()) throw std::invalid_argument("SetJointProperties: " + joined(refused, "; "));
    if (!ode.vel.empty()) world_.driveJoint(request.joint_name, ode.vel[0], ode.fmax[0]);
    return "SetJointProperties: properties set" +
           (unused.empty() ? "" : "; accepted but not used (ODE's solver settings): " + joinedNames(unused));
  });
}

bool GazeboServices::setModelConfiguration(gazebo_msgs::SetModelConfiguration::Request& request,
                                     gazebo_msgs::SetModelConfiguration::Response& response) {
  return answer(response, [&] {
    if (request.joint_names.size() != request.joint_positions.size()) {
      throw std::invalid_argument(
          "SetModelConfiguration: joint name and position list have different lengths");
    }
    std::map<std::string, double> positions;
    for (size_t i = 0; i < request.joint_names.size(); ++i) {
      positions[request.joint_names[i]] = request.joint_positions[i];
    }
    const std::string note = world_.setModelConfiguration(request.model_name, positions);
    if (note.empty()) return std::string("SetModelConfiguration: success");
    ROS_WARN("set_model_configuration of [%s]: %s", request.model_name.c_str(), note.c_str());
    return "SetModelConfiguration: success; " + note;
  });
}

bool GazeboServices::applyBodyWrench(gazebo_msgs::ApplyBodyWrench::Request& request,
                               gazebo_msgs::ApplyBodyWrench::Response& response) {
  return answer(response, [&] {
    BodyWrench wrench;
    wrench.body = request.body_name;
    wrench.reference_frame = request.reference_frame;
    tf2::fromMsg(request.reference_point, wrench.reference_point);
    tf2::fromMsg(request.wrench.force, wrench.force);
    tf2::fromMsg(request.wrench.torque, wrench.torque);
    wrench.schedule = {request.start_time.toSec(), request.duration.toSec()};
    return world_.applyBodyWrench(wrench);
  });
}

bool GazeboServices::clearBodyWrenches(gazebo_msgs::BodyRequest::Request& request,
                                 gazebo_msgs::BodyRequest::Response&) {
  try {
    world_.clearBodyWrenches(request.body_name);
  } catch (const std::exception& e) {
    ROS_WARN("clear_body_wrenches: %s", e.what());  // its response has no fields to say it in
  }
  return true;
}

bool GazeboServices::applyJointEffort(gazebo_msgs::ApplyJointEffort::Request& request,
                                gazebo_msgs::ApplyJointEffort::Response& response) {
  return answer(response, [&] {
    const std::string note = world_.applyJointEffort(
        {request.joint_name, request.effort, {request.start_time.toSec(), request.duration.toSec()}});
    return note.empty() ? "ApplyJointEffort: effort set" : note;
  });
}

bool GazeboServices::clearJointForces(gazebo_msgs::JointRequest::Request& request,
                                gazebo_msgs::JointRequest::Response&) {
  try {
    world_.clearJointEfforts(request.joint_name);
  } catch (const std::exception& e) {
    ROS_WARN("clear_joint_forces: %s", e.what());  // its response has no fields to say it in
  }
  return true;
}

bool GazeboServices::getPhysicsProperties(gazebo_msgs::GetPhysicsProperties::Request&,
                                    gazebo_msgs::GetPhysicsProperties::Response& response) {
  return answer(response, [&] {
    const PhysicsProperties physics = world_.physicsProperties();
    response.time_step = physics.step_size;
    response.pause = host_.paused();
    response.max_update_rate = physics.max_update_rate;
    tf2::toMsg(physics.gravity, response.gravity);
    response.ode_config = ode_;
    return "GetPhysicsProperties: got properties";
  });
}

bool GazeboServices::setPhysicsProperties(gazebo_msgs::SetPhysicsProperties::Request& request,
                                    gazebo_msgs::SetPhysicsProperties::Response& response) {
  return answer(response, [&] {
    // The ODE fields are only reported back, but a NaN in them would be too.
    const gazebo_msgs::ODEPhysics& ode = request.ode_config;
    for (const auto& [name, value] : {std::pair{"sor_pgs_w", ode.sor_pgs_w},
                                      {"sor_pgs_rms_error_tol", ode.sor_pgs_rms_error_tol},
                                      {"contact_surface_layer", ode.contact_surface_layer},
                                      {"contact_max_correcting_vel", ode.contact_max_correcting_vel},
                                      {"cfm", ode.cfm},
                                      {"erp", ode.erp}}) {
      requireFinite(value, std::string("SetPhysicsProperties: ode_config.") + name);
    }
    PhysicsProperties physics{request.time_step, request.max_update_rate, {}};
    tf2::fromMsg(request.gravity, physics.gravity);
    world_.setPhysicsProperties(physics);
    ode_ = request.ode_config;
    host_.physicsChanged();
    return std::string(
        "SetPhysicsProperties: time_step, max_update_rate and gravity set; the ODE fields "
        "auto_disable_bodies, "
        "sor_pgs_precon_iters, sor_pgs_iters, sor_pgs_w, sor_pgs_rms_error_tol, contact_surface_layer, "
        "contact_max_correcting_vel, cfm, erp and max_contacts are accepted and reported back, but not used: "
        "bullet_sim's solver is Bullet's");
  });
}

}  // namespace bullet_sim
