// joint_state_controller/JointStateController (ros_controllers, Noetic), ROS-free: the position, velocity and
// effort of every joint ros_control drives on joint_states, in the robot's namespace. Parameters:
//   publish_rate [Hz]  required, as in ros_controllers (0 publishes nothing)
//   joints             which joints, in what order (default: every one, in name order, as ros_control
//                      lists them)
//   extra_joints       a list of {name, position, velocity, effort}: joints published with those fixed
//                      values
#pragma once

#include <vector>

#include "plugins/ros_control/controller.h"

namespace bullet_sim {

class JointStateController : public Controller {
 public:
  explicit JointStateController(const ControllerSetup& setup);

 protected:
  void starting(double time) override;
  void onUpdate(double time, double period) override;
  void onReset() override { publish_time_set_ = false; }

 private:
  void addExtraJoints(const ControllerSetup& setup);

  double publish_rate_ = 0;  ///< [Hz]
  double last_publish_ = 0;
  bool publish_time_set_ = false;  ///< once set, a restart keeps the publishing grid, as ros_controllers does
  std::vector<const HardwareJoint*> joints_;
  Stream<JointStateSample> states_;
};

}  // namespace bullet_sim
