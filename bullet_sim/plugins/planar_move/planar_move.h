// libgazebo_ros_planar_move.so (gazebo_plugins on Noetic): cmd_vel's linear.x, linear.y and angular.z drive
// the robot holonomically. Before every step the root link gets that velocity, turned into the world by its
// yaw, with no vertical or tilting speed (Gazebo's Model::SetLinearVel and SetAngularVel); the ground's
// friction still acts within the step, as in Gazebo. Its tags, Noetic's with their defaults, are the table
// planarMoveTags() in planar_move.cpp.
// Odometry, every 1 / odometryRate: the pose of robotBaseFrame in the world (the root link's when it names
//   no link: Gazebo's model pose); its velocity from the poses' difference since the last odometry, in the
//   base frame; pose covariances 1e-5 (x, y), 1e-3 (yaw), 1e12 (z, roll, pitch). Noetic always publishes the
//   tf odometryFrame -> robotBaseFrame with it.
#pragma once

#include <string>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

/// What planar move and hector's force-based move share, filled from their tag tables (update_rate is the
/// odometryRate).
struct HolonomicConfig : PluginConfig {
  std::string command_topic;
  std::string odometry_topic;
  std::string odometry_frame;
  std::string robot_base_frame;
  double command_timeout = -1;      ///< [s]; < 0 = none (force-based move has no timeout)
  bool publish_odometry_tf = true;  ///< always, for planar move
};

struct PlanarMoveConfig : HolonomicConfig {};

void parsePlanarMove(const DeclarationSource& source, PlanarMoveConfig& config);

/// The rows of the tags planar move and force-based move share (readHolonomicTags reads them).
TagTable holonomicTags();
/// Reads the tags planar move and force-based move share into `config`.
void readHolonomicTags(const DeclarationSource& source, HolonomicConfig& config);

class PlanarMove : public Plugin {
 public:
  PlanarMove(const PluginDeclaration& declaration, const HolonomicConfig& config, const PluginSetup& setup);

  void applyCommands(const StepTime& time, RobotBody& body) override;
  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  /// The latest cmd_vel: linear.x and linear.y [m/s] and angular.z [rad/s]. Returns false, and changes
  /// nothing, when a value is not finite.
  bool setCommand(const Twist& command, double sim_time);

 protected:
  /// The command in force at `sim_time` (zero once it timed out): x [m/s], y [m/s], yaw rate [rad/s].
  Eigen::Vector3d command(double sim_time) const;
  /// The pose of the odometry's child frame in the world.
  Eigen::Isometry3d basePose(const RobotBody& body) const;
  /// Fills the odometry for `elapsed` [s] since the last one.
  virtual void fillOdometry(Odometry& odometry, const RobotBody& body, double elapsed);
  void onReset() override;

  const HolonomicConfig& holonomic() const { return config_; }

 private:
  HolonomicConfig config_;
  std::string pose_link_;  ///< robotBaseFrame, or the root link when that names no link
  Eigen::Vector3d command_ = Eigen::Vector3d::Zero();
  double command_time_ = 0;
  double last_odometry_ = 0;                ///< [s]
  std::optional<Eigen::Isometry3d> last_pose_;  ///< at the last odometry; none after a reset
  Stream<Odometry> odometry_;
  Stream<TransformSample> odometry_tf_;
};

}  // namespace bullet_sim
