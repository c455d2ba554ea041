// What the drive plugins share: their config head (cmd_vel, odometry, wheel model), the cmd_vel they follow,
// odometry with its tf, and the rule that says which way a wheel rolls.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

/// The config every drive starts with. Its parser fills it from the drive's tag table, whose defaults rule.
struct DriveConfigHead : PluginConfig {
  std::string command_topic;
  std::string odometry_topic;
  std::string odometry_frame;
  /// Gazebo's default, which readers of a drive's figures without a parser (ackermann_joint_commander) keep.
  std::string robot_base_frame = "base_footprint";
  /// The link the odometry follows and the wheels are measured in: robot_base_frame's, or the root link when
  /// it names none (Gazebo's drives follow the model, whose pose is its root link's).
  std::string base_link = "base_footprint";
  bool publish_odometry = false;  ///< odometry on odometry_topic
  bool publish_odom_tf = false;   ///< odometry_frame -> robot_base_frame on /tf
  double command_timeout = 0;     ///< [s]; 0 = off (ours: Gazebo keeps the last command for ever)
  std::string wheel_model;        ///< "contact" or "raycast" (ours)
  std::array<double, 36> pose_covariance{};
  std::array<double, 36> twist_covariance{};
};

/// The tag names a drive reads its head's fields under; where several are given, the first present wins (the
/// Ackermann drive takes ROS 2's names, and ROS 1's too). Each must have a row in the drive's tag table.
struct DriveTagNames {
  std::vector<std::string> command_topic{"commandTopic"};
  std::vector<std::string> odometry_topic{"odometryTopic"};
  std::vector<std::string> odometry_frame{"odometryFrame"};
  std::vector<std::string> robot_base_frame{"robotBaseFrame"};
};

/// The rows of our own tags that every drive reads alike (Gazebo ignores them): commandTimeout and
/// wheelModel.
std::vector<TagRow> ownDriveTagRows();

/// The default the plugin's tag table gives `tag`, for the readers that take an explicit fallback
/// (PluginTags::frame, capped); a std::logic_error when the table has no such row.
std::string tableDefault(const PluginTags& tags, const std::string& tag);
/// The same, as a number.
double tableDefaultNumber(const PluginTags& tags, const std::string& tag);

/// Reads the head through the drive's tag table: its topics and frames under `names`, then our commandTimeout
/// and wheelModel. The registry has read the update rate (the drive's RateRule).
void readDriveHead(PluginTags& tags, const DriveTagNames& names, DriveConfigHead& head);

/// A drive's plugin type's say in its robot's wheel model: its <wheelModel>.
std::optional<std::string> driveWheelModel(const PluginDeclaration& declaration);

/// A pose or twist covariance that knows x, y and yaw, and nothing (1e12) of z, roll and pitch.
std::array<double, 36> planarCovariance(double x, double y, double yaw);
/// Reads covariance_x, covariance_y and covariance_yaw (>= 0, the table's defaults) into the head's pose and
/// twist covariances (planarCovariance).
void readPlanarCovariance(PluginTags& tags, DriveConfigHead& head);
/// "x y z", as a URDF writes a vector.
std::string vectorText(const Eigen::Vector3d& v);

/// Whether a positive velocity of `joint` rolls its wheel forward (+1) or backward (-1) in `base_frame`: a
/// wheel spinning about the base's +y (its left) rolls forward, by REP 103. `poses` are the model's link
/// poses at zero (linkPosesAtZero).
double wheelRollSign(const std::map<std::string, Eigen::Isometry3d>& poses, const std::string& base_frame,
                     const JointSpec& joint);

/// The latest cmd_vel: forward speed [m/s] and turn rate [rad/s], zero once older than a timeout.
class VelocityCommand {
 public:
  /// `timeout` [s]: 0 keeps the last command for ever, as Gazebo does.
  explicit VelocityCommand(double timeout) : timeout_(timeout) {}

  /// Returns false, and changes nothing, when a value is not finite.
  bool set(double linear, double angular, double sim_time);
  /// The command in force through `step`: one older than the timeout at the step's start is not. (At its end,
  /// a world whose step exceeds the timeout dropped every command: the wheelchair, 0.5 s, stood still under
  /// 0.6 s steps.)
  double linear(const StepTime& step) const { return timedOut(step) ? 0.0 : linear_; }
  double angular(const StepTime& step) const { return timedOut(step) ? 0.0 : angular_; }
  void reset() { linear_ = angular_ = command_time_ = 0; }

 private:
  bool timedOut(const StepTime& step) const {
    return timeout_ > 0 && step.sim_time - step.dt - command_time_ > timeout_;
  }

  double timeout_;
  double linear_ = 0;
  double angular_ = 0;
  double command_time_ = 0;
};

/// A drive: it follows cmd_vel (its input) and publishes odometry and, when asked, its tf.
class DrivePlugin : public Plugin {
 public:
  DrivePlugin(const PluginDeclaration& declaration, const DriveConfigHead& head, const PluginSetup& setup);

  /// The latest cmd_vel: forward speed [m/s] and turn rate [rad/s]. Returns false, and changes nothing, when
  /// a value is not finite.
  bool setCommand(double linear, double angular, double sim_time);

 protected:
  const VelocityCommand& command() const { return command_; }
  /// The odometry to fill; publishOdometry() then makes it the latest, with its tf.
  Odometry& nextOdometry() { return odometry_.next(); }
  void publishOdometry();
  /// Gazebo's "world" odometry source: the base frame's pose in the world, its velocities in its own frame.
  void fillGroundTruth(const RobotBody& body, double stamp);
  void onReset() override;

 private:
  std::string base_frame_;
  VelocityCommand command_;
  Stream<Odometry> odometry_;
  Stream<TransformSample> odometry_tf_;
};

}  // namespace bullet_sim
