#include "plugins/ros_control/controller.h"

#include <algorithm>
#include <stdexcept>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/names.h"

namespace bullet_sim {

std::string stateName(ControllerState state) {
  switch (state) {
    case ControllerState::kInitialized:
      return "initialized";
    case ControllerState::kRunning:
      return "running";
    case ControllerState::kStopped:
      return "stopped";
  }
  return "unknown";
}

Controller::Controller(const ControllerSetup& setup, std::string hardware_interface)
    : name_(setup.name), type_(setup.type), hardware_(setup.hardware) {
  claims_.hardware_interface = std::move(hardware_interface);
}

void Controller::start(double time) {
  starting(time);
  state_ = ControllerState::kRunning;
  updated_ = false;
}

void Controller::stop(double time) {
  stopping(time);
  state_ = ControllerState::kStopped;
}

void Controller::update(double time, double period) {
  if (!running()) return;
  onUpdate(time, period);
  updated_ = true;
}

void Controller::restart(double time) {
  onReset();
  if (!running()) return;
  starting(time);
  updated_ = false;
}

HardwareJoint& Controller::claim(const std::string& joint, JointInterface interface) {
  HardwareJoint* found = hardware_.find(joint);
  if (!found || found->interface != interface) {
    std::vector<std::string> names = hardware_.namesOf(interface);
    std::string why = "joint [" + joint + "] ";
    why += found ? "is driven through " + interfaceName(found->interface) + " by its transmission"
                 : "has no transmission ros_control drives";
    throw std::invalid_argument(why + ", and this controller needs " + interfaceName(interface) +
                                didYouMean(joint, names) +
                                "; the joints driven through it: " + joinedNames(names, "none"));
  }
  if (std::count(claims_.resources.begin(), claims_.resources.end(), joint) == 0)
    claims_.resources.push_back(joint);
  return *found;
}

void Controller::warnUnread(const ControllerSetup& setup, const std::vector<std::string>& known) const {
  std::vector<std::string> names = known;
  names.push_back("type");
  for (const auto& key : setup.parameters.keys()) {
    if (std::count(names.begin(), names.end(), key)) continue;
    setup.warnings.push_back("controller [" + name_ + "]: parameter [" + key + "] is not one " + type_ +
                             " reads" + didYouMean(key, names) + ": ignored");
  }
}

}  // namespace bullet_sim
