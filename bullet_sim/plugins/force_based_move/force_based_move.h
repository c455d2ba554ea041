// libgazebo_ros_force_based_move.so (hector_gazebo_plugins on Noetic): cmd_vel's linear.x, linear.y and
// angular.z drive the robot holonomically through forces. Before every step robotBaseFrame gets, at its
// centre of mass, the force k_x (x - v_x), k_y (y - v_y) in its own axes (v: the root link's velocity in
// its frame) and the torque -k_yaw (w_z - angular.z) about the world's z.
//
// Its tags, hector's with their defaults, are the table forceBasedMoveTags() in force_based_move.cpp. A gain
// k with k dt / m >= 2 makes the velocity oscillate (as in Gazebo): a robot lighter than k dt / 2 needs
// smaller gains. There is no command timeout: the last command holds.
// Odometry is dead reckoning, as hector's: from the start pose, the root link's velocities in its frame,
//   integrated over each odometry period along an arc; hector's covariances.
#pragma once

#include <limits>

#include "plugins/planar_move/planar_move.h"

namespace bullet_sim {

struct ForceBasedMoveConfig : HolonomicConfig {
  double x_gain = 0;    ///< [N s/m]
  double y_gain = 0;    ///< [N s/m]
  double yaw_gain = 0;  ///< [N m s]
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();  ///< [m] of robotBaseFrame as Gazebo lumps it
  /// The most of the command's x [m/s], y [m/s] and yaw rate [rad/s] followed (nexus' copy caps them; a
  /// negative command is not capped, as there).
  Eigen::Vector3d command_cap = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
};

/// Planar move's tags, hector's gains and its tf switch.
TagTable forceBasedMoveTags();

void parseForceBasedMove(const DeclarationSource& source, ForceBasedMoveConfig& config);

/// The pose change of a body moving at `x`, `y` [m/s] in its frame and turning at `yaw_rate` [rad/s] for
/// `seconds`, along hector's arc.
Eigen::Isometry3d motionOver(double x, double y, double yaw_rate, double seconds);

class ForceBasedMove : public PlanarMove {
 public:
  ForceBasedMove(const PluginDeclaration& declaration, const ForceBasedMoveConfig& config,
                 const PluginSetup& setup);

  void applyCommands(const StepTime& time, RobotBody& body) override;

 private:
  void fillOdometry(Odometry& odometry, const RobotBody& body, double elapsed) override;
  void onReset() override;

  ForceBasedMoveConfig config_;
  Eigen::Isometry3d odometry_pose_ = Eigen::Isometry3d::Identity();
};

}  // namespace bullet_sim
