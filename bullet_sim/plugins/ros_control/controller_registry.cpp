#include "plugins/ros_control/controller_registry.h"

#include <algorithm>

#include "plugins/ros_control/diff_drive_controller.h"
#include "plugins/ros_control/joint_command_controllers.h"
#include "plugins/ros_control/joint_state_controller.h"
#include "plugins/ros_control/joint_trajectory_controller.h"
#include "plugins/ros_control/pid_joint_controllers.h"

namespace bullet_sim {

namespace {

ControllerRegistry makeBuiltinControllers() {
  using Joints = JointGroupCommandController;
  using Pid = PidJointController;
  using Trajectory = JointTrajectoryController;
  constexpr auto kEffort = JointInterface::kEffort, kVelocity = JointInterface::kVelocity,
                 kPosition = JointInterface::kPosition;
  ControllerRegistry registry;
  for (ControllerType type : {
           controllerType<JointStateController>("joint_state_controller/JointStateController"),
           controllerType<DiffDriveController>("diff_drive_controller/DiffDriveController"),
           controllerType<Joints>("velocity_controllers/JointVelocityController", kVelocity, true),
           controllerType<Joints>("position_controllers/JointPositionController", kPosition, true),
           controllerType<Joints>("effort_controllers/JointEffortController", kEffort, true),
           controllerType<Pid>("effort_controllers/JointPositionController", Pid::Target::kPosition),
           controllerType<Pid>("effort_controllers/JointVelocityController", Pid::Target::kVelocity),
           controllerType<Joints>("velocity_controllers/JointGroupVelocityController", kVelocity, false),
           controllerType<Joints>("position_controllers/JointGroupPositionController", kPosition, false),
           controllerType<Joints>("effort_controllers/JointGroupEffortController", kEffort, false),
           controllerType<Trajectory>("position_controllers/JointTrajectoryController", kPosition),
           controllerType<Trajectory>("velocity_controllers/JointTrajectoryController", kVelocity),
           controllerType<Trajectory>("effort_controllers/JointTrajectoryController", kEffort),
       }) {
    registry.add(std::move(type));
  }
  return registry;
}

}  // namespace

const ControllerRegistry& ControllerRegistry::builtin() {
  static const ControllerRegistry registry = makeBuiltinControllers();
  return registry;
}

void ControllerRegistry::add(ControllerType type) {
  auto same = std::find_if(types_.begin(), types_.end(),
                           [&](const ControllerType& known) { return known.name == type.name; });
  if (same != types_.end()) {
    *same = std::move(type);
  } else {
    types_.push_back(std::move(type));
  }
}

const ControllerType* ControllerRegistry::find(const std::string& name) const {
  for (const auto& type : types_) {
    if (type.name == name) return &type;
  }
  return nullptr;
}

std::vector<std::string> ControllerRegistry::names() const {
  std::vector<std::string> names;
  for (const auto& type : types_) names.push_back(type.name);
  return names;
}

}  // namespace bullet_sim
