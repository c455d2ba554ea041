// Wheeled drives with Gazebo classic's (Noetic) semantics:
//   libgazebo_ros_diff_drive.so        two wheels; wheelAcceleration ramp; odometrySource world | encoder
//   libgazebo_ros_skid_steer_drive.so  four wheels, each side driven alike; ground-truth odometry
// Both follow REP 103: +angular.z turns counter-clockwise. Each side's rim speed is v -/+ w * separation / 2.
// Their tags, with Gazebo's names and defaults and our commandTimeout and wheelModel, are the tables
// diffDriveTags() and skidSteerTags() in wheeled_drive.cpp.
//
// Unlike Gazebo, a wheel whose joint axis points the other way (e.g. 0 -1 0 on the right) is driven with the
// sign that rolls the robot forward, and that is said at load.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/drive_support.h"
#include "bullet_sim/plugins/plugin_checks.h"

namespace bullet_sim {

struct DriveConfig : DriveConfigHead {
  std::vector<std::string> left_joints;
  std::vector<std::string> right_joints;
  std::vector<double> left_signs;   ///< per left joint: +1 when a positive velocity rolls it forward
  std::vector<double> right_signs;  ///< the same for the right joints
  double wheel_separation = 0;      ///< [m]
  double encoder_separation = 0;    ///< [m] encoder odometry's: wheel_separation, or when 0 the joints'
  double wheel_diameter = 0;        ///< [m]
  double torque = 0;                ///< [N m] per wheel
  double acceleration = 0;          ///< [m/s^2] rim acceleration limit; 0 = none
  bool odometry_from_encoders = false;
  bool publish_wheel_joint_state = false;
  bool publish_wheel_tf = false;
};

/// Read and checked against the model: the joints exist and move, the base frame exists, the figures agree
/// with the URDF geometry. Problems go to the source's diagnostics.
void parseDiffDrive(const DeclarationSource& source, DriveConfig& config);
void parseSkidSteer(const DeclarationSource& source, DriveConfig& config);
/// The left wheels, then the right.
std::vector<std::string> driveWheels(const DriveConfig& config);
/// urdf_doctor's check of either drive (doctor_check.cpp): wheels that roll backwards, zero limits on them.
std::vector<PluginFinding> checkWheeledDrive(const PluginCheckInput& input);

class WheeledDrive : public DrivePlugin {
 public:
  WheeledDrive(const PluginDeclaration& declaration, const DriveConfig& config, const PluginSetup& setup);

  void applyCommands(const StepTime& time, RobotBody& body) override;
  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const DriveConfig& config() const { return config_; }

 private:
  struct Wheel {
    int joint = -1;
    double sign = 1;       ///< +1 when a positive joint velocity rolls the robot forward
    double rim_speed = 0;  ///< commanded, after the acceleration ramp [m/s]
    double last_position = 0;
    std::string parent_link, link;  ///< for publishWheelTF
  };

  void onReset() override;
  /// Advances the encoder pose by the wheels' travel since the last update: returns distance [m] and turn
  /// [rad].
  Eigen::Vector2d integrateEncoders(const RobotBody& body);
  void publishWheels(const StepTime& time, const RobotBody& body);

  DriveConfig config_;
  std::vector<Wheel> left_;
  std::vector<Wheel> right_;
  bool updated_this_step_ = false;
  double last_update_ = 0;
  Eigen::Vector3d encoder_pose_ = Eigen::Vector3d::Zero();  ///< x [m], y [m], yaw [rad]
  Stream<JointStateSample> wheel_states_;
  Stream<TransformSample> wheel_tf_;
};

}  // namespace bullet_sim
