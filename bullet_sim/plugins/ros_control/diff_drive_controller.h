// diff_drive_controller/DiffDriveController (ros_controllers, Noetic), ROS-free. It follows
// geometry_msgs/Twist on <name>/cmd_vel through the velocity joints of its wheels and publishes odometry on
// <name>/odom and, with enable_odom_tf, on /tf. Parameters, with ros_controllers' defaults:
//   left_wheel, right_wheel      a joint name or a list (as many on each side); required
//   wheel_separation [m], wheel_radius [m]   from the URDF when absent: the distance between the first left
//                                and right wheels' joint origins, and the first left wheel's collision radius
//   wheel_separation_multiplier [1], wheel_radius_multiplier [1] (else left_/right_wheel_radius_multiplier)
//   publish_rate [50 Hz], base_frame_id [base_link], odom_frame_id [odom], enable_odom_tf [true],
//   open_loop [false], velocity_rolling_window_size [10], pose_covariance_diagonal, twist_covariance_diagonal
//   (6 each), cmd_vel_timeout [0.5 s], allow_multiple_cmd_vel_publishers [true], publish_cmd [false: the
//   limited command on <name>/cmd_vel_out], linear/x/* and angular/z/* (SpeedLimiter)
#pragma once

#include <string>
#include <vector>

#include "plugins/ros_control/controller.h"
#include "plugins/ros_control/diff_drive_odometry.h"

namespace bullet_sim {

class DiffDriveController : public Controller {
 public:
  explicit DiffDriveController(const ControllerSetup& setup);

  const DiffDriveOdometry& odometry() const { return odometry_; }
  double wheelSeparation() const { return wheel_separation_; }  ///< [m], before its multiplier
  double wheelRadius() const { return wheel_radius_; }          ///< [m], before its multipliers

 protected:
  void starting(double time) override;
  void stopping(double time) override;
  void onUpdate(double time, double period) override;
  void onReset() override;

 private:
  struct Command {
    double linear = 0;   ///< [m/s]
    double angular = 0;  ///< [rad/s]
    double stamp = 0;    ///< [s] when it arrived
  };

  void readWheels(const ControllerSetup& setup);
  void readGeometry(const ControllerSetup& setup);
  void readOdometryFields(const ControllerSetup& setup);
  std::string takeCommand(const Twist& twist, double sim_time);
  void integrateOdometry(double time);
  void publishOdometry(double time);
  /// The command in force at `time`, limited.
  Command limitedCommand(double time, double period);
  void setWheels(double left, double right);

  std::vector<HardwareJoint*> left_, right_;
  double wheel_separation_ = 0, wheel_radius_ = 0;
  double separation_multiplier_ = 1, left_radius_multiplier_ = 1, right_radius_multiplier_ = 1;
  double publish_period_ = 0.02;  ///< [s]
  double last_publish_ = 0;
  bool open_loop_ = false;
  bool enable_odom_tf_ = true;
  bool publish_cmd_ = false;
  bool allow_multiple_publishers_ = true;
  double cmd_vel_timeout_ = 0.5;  ///< [s]
  SpeedLimiter linear_limiter_, angular_limiter_;
  Command received_, last0_, last1_;  ///< the latest cmd_vel, and the commands of the last two updates
  DiffDriveOdometry odometry_;
  Stream<Odometry> odom_;
  Stream<TransformSample> odom_tf_;
  Stream<StampedTwist> command_out_;
  Publishers command_publishers_;
};

}  // namespace bullet_sim
