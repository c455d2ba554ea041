#include "plugins/ros_control/ros_control_plugin.h"

#include <set>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/names.h"
#include "bullet_sim/plugins/registry.h"
#include "plugins/ros_control/controller_registry.h"

namespace bullet_sim {

namespace {

constexpr const char* kDefaultSimType = "gazebo_ros_control/DefaultRobotHWSim";

TagTable rosControlTags() {
  return {
      {"robotNamespace", TagType::kText, "the model's name", "",
       "the namespace of the controller manager and of its controllers' parameters", ""},
      {"controlPeriod", TagType::kPositive, "0", "s",
       "the controllers' update period; the physics step when absent",
       "0 (or absent): every step; the simulation's rate limit caps it"},
      {"robotParam", TagType::kIgnored, "robot_description", "",
       "the parameter holding the URDF whose transmissions it drives",
       "the URDF the robot was spawned from is driven"},
      {"eStopTopic", TagType::kTopic, "", "",
       "a std_msgs/Bool topic: true is an emergency stop that holds every joint; none when absent", ""},
      {"robotSimType", TagType::kText, kDefaultSimType, "", "the RobotHWSim plugin that drives the joints",
       "only its default is simulated: another is an error"},
      {"legacyModeNS", TagType::kIgnored, "", "",
       "not read on Noetic; Kinetic's made DefaultRobotHWSim ignore robotNamespace",
       "ignored with a warning"},
      {"wheelModel", TagType::kText, "", "", "not read (bullet_sim's tag)",
       "the robot's wheel-ground model, contact or raycast; when absent, chosen by the controllers and "
       "transmissions (see the reference's ros_control page)"},
  };
}

/// The interface a <hardwareInterface> names, in either of ros_control's spellings; nullopt for another.
std::optional<JointInterface> interfaceNamed(const std::string& name, bool* deprecated) {
  static const std::pair<const char*, JointInterface> kInterfaces[] = {
      {"EffortJointInterface", JointInterface::kEffort},
      {"VelocityJointInterface", JointInterface::kVelocity},
      {"PositionJointInterface", JointInterface::kPosition}};
  for (const auto& [bare, interface] : kInterfaces) {
    *deprecated = name == bare;
    if (*deprecated || name == std::string("hardware_interface/") + bare) return interface;
  }
  return std::nullopt;
}

std::vector<std::string> movingJoints(const ModelSpec& model) {
  std::vector<std::string> names;
  for (const auto& joint : model.joints) {
    if (joint.moves()) names.push_back(joint.name);
  }
  return names;
}

/// The joint of one transmission as DefaultRobotHWSim drives it, or nullopt after a problem in `diagnostics`.
std::optional<DrivenJoint> drivenJoint(const TransmissionSpec& transmission, const ModelSpec& model,
                                       const std::string& where, Diagnostics& diagnostics) {
  const std::string head = where + " " + transmission.where();
  if (transmission.joints.size() > 1) {
    diagnostics.warning(head + " has " + std::to_string(transmission.joints.size()) +
                        " joints, and DefaultRobotHWSim drives one joint per transmission: skipped");
    return std::nullopt;
  }
  const TransmissionJoint& joint = transmission.joints.front();
  const JointSpec* spec = model.joint(joint.name);
  if (!spec || !spec->moves()) {
    diagnostics.error(head + " names joint [" + joint.name + "], which " +
                      (spec ? "is fixed (Gazebo merges fixed joints away)" : "the robot does not have") +
                      didYouMean(joint.name, movingJoints(model)));
    return std::nullopt;
  }
  const std::string& name = joint.hardware_interfaces.front();
  if (joint.hardware_interfaces.size() > 1) {
    diagnostics.warning(head + " joint [" + joint.name +
                        "] names several hardware interfaces: DefaultRobotHWSim "
                        "drives it through the first, [" +
                        name + "]");
  }
  bool deprecated = false;
  const auto interface = interfaceNamed(name, &deprecated);
  if (!interface) {
    diagnostics.error(
        head + " joint [" + joint.name + "] <hardwareInterface> [" + name +
        "] is not one DefaultRobotHWSim drives: use hardware_interface/EffortJointInterface, "
        "hardware_interface/VelocityJointInterface or hardware_interface/PositionJointInterface");
    return std::nullopt;
  }
  if (deprecated) {
    diagnostics.warning(head + " joint [" + joint.name + "] <hardwareInterface> [" + name +
                        "] is the deprecated spelling of [hardware_interface/" + name +
                        "]: it is read as that");
  }
  return DrivenJoint{joint.name, *interface};
}

std::vector<DrivenJoint> drivenJoints(const DeclarationSource& source) {
  std::vector<DrivenJoint> joints;
  std::set<std::string> seen;
  for (const auto& transmission : source.model.transmissions) {
    const auto joint = drivenJoint(transmission, source.model, source.tags.where(), source.diagnostics);
    if (!joint) continue;
    if (!seen.insert(joint->name).second) {
      source.diagnostics.warning(source.tags.where() + " " + transmission.where() + " drives joint [" +
                                 joint->name + "] again: the first transmission of it is used");
      continue;
    }
    joints.push_back(*joint);
  }
  return joints;
}

/// `joints` but the followers of a mimic coupling (which moves them), each left out with a warning: Noetic's
/// DefaultRobotHWSim has no mimic support, so driving one would fight the coupling.
std::vector<DrivenJoint> withoutFollowers(const std::vector<DrivenJoint>& joints, const ModelSpec& model,
                                          std::vector<std::string>& warnings) {
  std::vector<DrivenJoint> driven;
  for (const DrivenJoint& joint : joints) {
    const JointSpec* spec = model.joint(joint.name);
    if (spec && spec->mimic) {
      warnings.push_back("joint [" + joint.name + "] follows [" + spec->mimic->joint + "] by " +
                         spec->mimic->source + ": ros_control does not drive it, its coupling does");
    } else {
      driven.push_back(joint);
    }
  }
  return driven;
}

/// The joints named as wheels by the robot's diff_drive_controllers.
std::set<std::string> diffDriveWheels(const ParameterTree& robot_parameters) {
  std::set<std::string> wheels;
  for (const auto& key : robot_parameters.keys()) {
    try {
      const ParameterTree controller = robot_parameters.at(key);
      if (controller.text("type", "") != "diff_drive_controller/DiffDriveController") continue;
      for (const char* side : {"left_wheel", "right_wheel"}) {
        for (const auto& wheel : controller.texts(side)) wheels.insert(wheel);
      }
    } catch (const SpecError&) {
      // Not a controller's parameters; load_controller reports them if they are.
    }
  }
  return wheels;
}

}  // namespace

void parseRosControl(const DeclarationSource& source, RosControlConfig& config) {
  PluginTags& tags = source.tags;
  config.namespace_given = tags.has("robotNamespace");
  config.control_period = tags.nonNegative("controlPeriod");
  config.update_rate = config.control_period > 0 ? 1 / config.control_period : 0;
  config.e_stop_topic = tags.text("eStopTopic");
  const std::string sim_type = tags.text("robotSimType");
  if (sim_type != kDefaultSimType) {
    source.diagnostics.error(tags.where() + " <robotSimType> [" + sim_type +
                             "] is a RobotHWSim bullet_sim does not have: only " + kDefaultSimType +
                             " is simulated (leave the tag out to use it)");
  }
  if (tags.has("legacyModeNS")) {
    source.diagnostics.warning(tags.where() +
                               " <legacyModeNS> is gone from Noetic's gazebo_ros_control: ignored");
  }
  config.wheel_model = tags.text("wheelModel");
  if (!config.wheel_model.empty() && config.wheel_model != "contact" && config.wheel_model != "raycast") {
    source.diagnostics.error(tags.where() + " <wheelModel> must be contact or raycast, not [" +
                             config.wheel_model + "]");
    config.wheel_model.clear();
  }
  config.joints = drivenJoints(source);
}

std::string rosControlNamespace(const RosControlConfig& config, const std::string& robot_name,
                                const std::optional<std::string>& spawn_namespace) {
  if (spawn_namespace) return withoutSlashes(*spawn_namespace);
  return withoutSlashes(config.namespace_given ? config.robot_namespace : robot_name);
}

std::string rosControlWheelModel(const RosControlConfig& config, const ModelSpec& model,
                                 const ParameterTree& robot_parameters, Diagnostics& diagnostics) {
  std::set<std::string> wheels = diffDriveWheels(robot_parameters);
  if (wheels.empty()) {
    for (const auto& joint : config.joints) {
      const JointSpec* spec = model.joint(joint.name);
      if (spec && spec->type == JointSpec::Type::kContinuous && joint.interface != JointInterface::kPosition)
        wheels.insert(joint.name);
    }
  }
  std::string pushed;  // a joint other than a wheel that is pushed by effort
  for (const auto& joint : config.joints) {
    if (wheels.count(joint.name) || !pushed.empty()) continue;
    const bool pid =
        Pid::gainsFrom(robot_parameters.at("gazebo_ros_control/pid_gains/" + joint.name)).has_value();
    if (joint.interface == JointInterface::kEffort || pid) pushed = joint.name;
  }
  if (config.wheel_model == "raycast" && !pushed.empty()) {
    diagnostics.error("libgazebo_ros_control.so <wheelModel>raycast</wheelModel> moves the joints other than "
                      "wheels kinematically, so it cannot push joint [" + pushed +
                      "] by effort (its transmission or its pid_gains ask for that): use contact");
  }
  if (!config.wheel_model.empty()) return config.wheel_model;
  if (wheels.empty() || !pushed.empty()) return "contact";
  return kDefaultWheelModel;
}

RosControl::RosControl(const PluginDeclaration& declaration, const RosControlConfig& config,
                       const PluginSetup& setup)
    : Plugin(declaration, setup), body_(setup.body) {
  const std::string ns = rosControlNamespace(config, setup.robot_name, setup.robot_namespace);
  setRobotNamespace(ns);
  const ParameterTree parameters = setup.parameters ? setup.parameters->fetch("/" + ns) : ParameterTree();
  std::vector<std::string> warnings;
  const std::vector<DrivenJoint> joints = withoutFollowers(config.joints, setup.body.spec(), warnings);
  hardware_ = std::make_unique<RobotHardware>(joints, setup.body, parameters, &warnings);
  for (const auto& warning : warnings) {
    if (setup.diagnostics) setup.diagnostics->warning(where() + ": " + warning);
  }
  manager_ = std::make_unique<ControllerManager>(*hardware_, ControllerRegistry::builtin(), setup.parameters,
                                                 ns, setup.body.spec());
  if (!config.e_stop_topic.empty()) {
    addInput<BoolCommand>(config.e_stop_topic, [this](const BoolCommand& command, double) {
      e_stop_ = command.data;
      return std::string();
    });
  }
  serveControllerManager();
}

void RosControl::serveControllerManager() {
  addService<LoadControllerRequest>(
      "controller_manager/load_controller",
      [this](const LoadControllerRequest& request, LoadControllerRequest::Reply& reply) {
        return manager_->load(request.name, &reply.warnings);
      });
  addService<UnloadControllerRequest>("controller_manager/unload_controller",
                                      [this](const UnloadControllerRequest& request) {
                                        return manager_->unload(request.name);
                                      });
  addService<SwitchControllerRequest>(
      "controller_manager/switch_controller",
      [this](const SwitchControllerRequest& request, SwitchControllerRequest::Reply& reply) {
        return switchControllers(request, &reply.warnings);
      });
  addService<ListControllersRequest>(
      "controller_manager/list_controllers",
      [this](const ListControllersRequest&, ListControllersRequest::Reply& reply) {
        reply.controllers = manager_->list();
        return std::string();
      });
  addService<ListControllerTypesRequest>(
      "controller_manager/list_controller_types",
      [this](const ListControllerTypesRequest&, ListControllerTypesRequest::Reply& reply) {
        reply = manager_->listTypes();
        return std::string();
      });
  addService<ReloadControllerLibrariesRequest>("controller_manager/reload_controller_libraries",
                                               [this](const ReloadControllerLibrariesRequest& request) {
                                                 return manager_->reloadLibraries(request.force_kill, now_);
                                               });
}

std::string RosControl::switchControllers(const SwitchControllerRequest& request,
                                          std::vector<std::string>* warnings) {
  hardware_->read(body_);
  return manager_->switchControllers(request, now_, warnings);
}

std::vector<std::string> RosControl::jointsPlaced(const RobotBody& body) {
  hardware_->read(body);
  std::vector<std::string> warnings = manager_->startUnupdatedAgain(now_);
  for (auto& warning : warnings) warning = where() + ": " + warning;
  return warnings;
}

void RosControl::applyCommands(const StepTime& time, RobotBody& body) {
  if (restart_pending_) {  // a reset happened at the end of the last step
    last_update_ = time.sim_time - time.dt;
    manager_->restart(last_update_);
    restart_pending_ = false;
  }
  if (timer().due(time)) {
    hardware_->read(body);
    const bool released = was_e_stopped_ && !e_stop_;  // ros_control restarts the controllers then
    was_e_stopped_ = e_stop_;
    manager_->update(time.sim_time, time.sim_time - last_update_, released);
    last_update_ = time.sim_time;
  }
  hardware_->write(body, time.dt, e_stop_);
  now_ = time.sim_time;
}

void RosControl::onReset() {
  hardware_->reset();
  e_stop_ = was_e_stopped_ = false;
  restart_pending_ = true;
}

BULLET_SIM_PLUGIN_FOLDER(ros_control) {
  PluginType type = pluginType<RosControl>("libgazebo_ros_control.so", parseRosControl, rosControlTags());
  type.needs = kNeedParameters;
  type.tf_prefix = TfPrefixRule::kNone;  // its controllers name their frames as their parameters say
  type.check = [](const PluginCheckInput& input) {  // urdf_doctor's: zero limits on the joints it drives
    std::vector<std::string> motors;
    for (const DrivenJoint& joint : input.declaration.configAs<RosControlConfig>()->joints)
      motors.push_back(joint.name);
    return checks::zeroLimitsOnMotors(
        input, motors,
        "ros_control drives it through a <transmission>, and Gazebo freezes such a joint too "
        "(gazebo_ros_control's fmax is the effort limit, and it saturates commands at the velocity limit)");
  };
  type.wheel_model = [](const PluginDeclaration& declaration, const WheelModelQuery& query) {
    const auto& config = *declaration.configAs<RosControlConfig>();
    const std::string ns = rosControlNamespace(config, query.robot_name, query.robot_namespace);
    const ParameterTree parameters = query.parameters ? query.parameters->fetch("/" + ns) : ParameterTree();
    return std::optional<std::string>(
        rosControlWheelModel(config, query.model, parameters, query.diagnostics));
  };
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
