#include "plugins/ros_control/joint_command_controllers.h"

#include <stdexcept>

namespace bullet_sim {

JointGroupCommandController::JointGroupCommandController(const ControllerSetup& setup,
                                                         JointInterface interface, bool single)
    : Controller(setup, interfaceName(interface)), interface_(interface) {
  const char* parameter = single ? "joint" : "joints";
  warnUnread(setup, {parameter});
  const std::vector<std::string> names = single ? std::vector<std::string>{setup.parameters.text("joint", "")}
                                                : setup.parameters.texts("joints");
  if (names.empty() || names.front().empty()) {
    throw std::invalid_argument(std::string(parameter) + " is not set: give the joint" + (single ? "" : "s") +
                                " to command");
  }
  for (const auto& name : names) joints_.push_back(&claim(name, interface));
  commands_.assign(joints_.size(), 0.0);
  if (single) {
    ownPorts().addInput<Float64Command>(topic("command"), [this](const Float64Command& command, double) {
      commands_.front() = command.data;
      return std::string();
    });
    return;
  }
  ownPorts().addInput<Float64ArrayCommand>(topic("command"), [this](const Float64ArrayCommand& command,
                                                                    double) {
    if (command.data.size() != commands_.size()) {
      return "a command of " + std::to_string(command.data.size()) + " values for controller [" + name() +
             "], which has " + std::to_string(commands_.size()) + " joints: not executed";
    }
    commands_ = command.data;
    return std::string();
  });
}

void JointGroupCommandController::starting(double) {
  for (size_t i = 0; i < joints_.size(); ++i)
    commands_[i] = interface_ == JointInterface::kPosition ? joints_[i]->position : 0.0;
}

void JointGroupCommandController::onUpdate(double, double) {
  for (size_t i = 0; i < joints_.size(); ++i) joints_[i]->command = commands_[i];
}

}  // namespace bullet_sim
