// effort_controllers/JointPositionController and effort_controllers/JointVelocityController (ros_controllers,
// Noetic), ROS-free: a PID loop pushes an effort joint towards the position or velocity last given on
// <name>/command (std_msgs/Float64), and every 10th update publishes control_msgs/JointControllerState on
// <name>/state. Parameters: joint; pid/p (required), pid/i, pid/d, pid/i_clamp (or i_clamp_min, i_clamp_max),
// pid/antiwindup. The position controller keeps its target within the URDF's limits, and takes a continuous
// joint the shortest way round.
#pragma once

#include "plugins/ros_control/controller.h"
#include "plugins/ros_control/pid.h"

namespace bullet_sim {

class PidJointController : public Controller {
 public:
  enum class Target { kPosition, kVelocity };

  PidJointController(const ControllerSetup& setup, Target target);

  double setPoint() const { return set_point_; }

 protected:
  void starting(double time) override;
  void onUpdate(double time, double period) override;

 private:
  /// The target within the URDF's limits (position controllers of revolute and prismatic joints).
  double limited(double position) const;
  /// set_point - what the joint does now.
  double error() const;
  void publishState(double time, double period, double error, double effort);

  Target target_;
  HardwareJoint* joint_ = nullptr;
  Pid pid_;
  double set_point_ = 0;  ///< [rad], [m], [rad/s] or [m/s]
  uint64_t updates_ = 0;
  Stream<JointControllerState> state_;
};

}  // namespace bullet_sim
