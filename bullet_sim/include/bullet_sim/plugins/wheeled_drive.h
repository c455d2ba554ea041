// Wheeled drives with Gazebo classic's (Noetic) semantics:
//   libgazebo_ros_diff_drive.so        two wheels; wheelAcceleration ramp; odometrySource world | encoder
//   libgazebo_ros_skid_steer_drive.so  four wheels, each side driven alike; ground-truth odometry
// Both follow REP 103: +angular.z turns counter-clockwise. Each side's rim speed is v -/+ w * separation / 2.
//
// Tags (Gazebo's names and defaults):
//   commandTopic [cmd_vel] odometryTopic [odom] odometryFrame [odom] robotBaseFrame [base_footprint]
//   robotNamespace updateRate [100 Hz; 0 = every step] wheelSeparation [m] wheelDiameter [m]
//   diff drive: leftJoint rightJoint wheelTorque [5 N m] wheelAcceleration [0 m/s^2 = none]
//               odometrySource [world] publishTf [true: gates odom] publishOdomTF [true]
//               publishWheelJointState [false] publishWheelTF [false] legacyMode (read, ignored)
//   skid steer: leftFrontJoint rightFrontJoint leftRearJoint rightRearJoint torque [5 N m]
//               broadcastTF [false] covariance_x [1e-4] covariance_y [1e-4] covariance_yaw [0.01]
// Ours (Gazebo ignores them): commandTimeout [0 s = off] stops the robot when cmd_vel falls silent;
//   wheelModel [contact] chooses the wheel-ground model.
//
// Unlike Gazebo, a wheel whose joint axis points the other way (e.g. 0 -1 0 on the right) is driven with the
// sign that rolls the robot forward, and that is said at load.
#pragma once

#include <array>
#include <random>
#include <string>
#include <vector>

#include "bullet_sim/plugins/drive_support.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct DriveConfig {
  std::string robot_namespace;
  std::string command_topic = "cmd_vel";
  std::string odometry_topic = "odom";
  std::string odometry_frame = "odom";
  std::string robot_base_frame = "base_footprint";
  std::vector<std::string> left_joints;
  std::vector<std::string> right_joints;
  double wheel_separation = 0.34;  ///< [m]
  double wheel_diameter = 0.15;    ///< [m]
  double torque = 5.0;             ///< [N m] per wheel
  double acceleration = 0;         ///< [m/s^2] rim acceleration limit; 0 = none
  double update_rate = 100;        ///< [Hz]; 0 = every step
  bool odometry_from_encoders = false;
  bool publish_odometry = true;
  bool publish_odom_tf = true;
  bool publish_wheel_joint_state = false;
  bool publish_wheel_tf = false;
  double command_timeout = 0;  ///< [s]; 0 = off
  std::string wheel_model = kDefaultWheelModel;
  std::array<double, 36> pose_covariance{};
  std::array<double, 36> twist_covariance{};
};

DriveConfig parseDiffDriveConfig(PluginTags& tags);
DriveConfig parseSkidSteerConfig(PluginTags& tags);

class WheeledDrive : public Plugin {
 public:
  /// Checks the config against the model: joints exist and move, the base frame exists, the figures agree
  /// with the URDF geometry. Problems go to `diagnostics`.
  WheeledDrive(std::string name, DriveConfig config, const ModelSpec& model, const RobotBody& body,
               Diagnostics& diagnostics);

  /// The latest cmd_vel: forward speed [m/s] and turn rate [rad/s]. Returns false, and changes nothing, when
  /// a value is not finite.
  bool setCommand(double linear, double angular, double sim_time);

  void applyCommands(const StepTime& time, RobotBody& body) override;
  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;
  void reset() override;

  const DriveConfig& config() const { return config_; }
  /// The latest odometry, and how many have been produced (a new one when the count changes).
  const Odometry& odometry() const { return odometry_; }
  uint64_t odometryCount() const { return odometry_count_; }
  const JointStateSample& wheelJointStates() const { return wheel_states_; }
  uint64_t wheelJointStatesCount() const { return wheel_states_count_; }

 private:
  struct Wheel {
    int joint = -1;
    double sign = 1;       ///< +1 when a positive joint velocity rolls the robot forward
    double rim_speed = 0;  ///< commanded, after the acceleration ramp [m/s]
    double last_position = 0;
  };

  /// Advances the encoder pose by the wheels' travel since the last update: returns distance [m] and turn
  /// [rad].
  Eigen::Vector2d integrateEncoders(const RobotBody& body);

  DriveConfig config_;
  std::vector<Wheel> left_;
  std::vector<Wheel> right_;
  UpdateTimer timer_;
  bool updated_this_step_ = false;
  double last_update_ = 0;
  VelocityCommand command_;
  Eigen::Vector3d encoder_pose_ = Eigen::Vector3d::Zero();  ///< x [m], y [m], yaw [rad]
  Odometry odometry_;
  uint64_t odometry_count_ = 0;
  JointStateSample wheel_states_;
  uint64_t wheel_states_count_ = 0;
};

}  // namespace bullet_sim
