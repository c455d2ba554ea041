// ros_controllers' forward command controllers (Noetic), ROS-free: they pass the last command straight to
// their joints' command interface.
//   velocity_controllers/JointVelocityController, position_controllers/JointPositionController,
//   effort_controllers/JointEffortController: parameter `joint`; std_msgs/Float64 on <name>/command.
//   velocity_controllers/JointGroupVelocityController, position_controllers/JointGroupPositionController,
//   effort_controllers/JointGroupEffortController: parameter `joints` (a list); std_msgs/Float64MultiArray on
//   <name>/command, one value per joint.
// When one starts, its command is the joints' position (position controllers) or 0.
#pragma once

#include <vector>

#include "plugins/ros_control/controller.h"

namespace bullet_sim {

class JointGroupCommandController : public Controller {
 public:
  /// A group controller on `interface`, or with `single` the one-joint controller.
  JointGroupCommandController(const ControllerSetup& setup, JointInterface interface, bool single);

  const std::vector<double>& commands() const { return commands_; }

 protected:
  void starting(double time) override;
  void onUpdate(double time, double period) override;

 private:
  JointInterface interface_;
  std::vector<HardwareJoint*> joints_;
  std::vector<double> commands_;
};

}  // namespace bullet_sim
