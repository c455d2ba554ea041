// What the drive plugins share: the cmd_vel they follow, and ground-truth odometry.
#pragma once

#include <string>

#include "bullet_sim/physics/robot_body.h"
#include "bullet_sim/plugins/outputs.h"

namespace bullet_sim {

/// The latest cmd_vel: forward speed [m/s] and turn rate [rad/s], zero once older than a timeout.
class VelocityCommand {
 public:
  /// `timeout` [s]: 0 keeps the last command for ever, as Gazebo does.
  explicit VelocityCommand(double timeout) : timeout_(timeout) {}

  /// Returns false, and changes nothing, when a value is not finite.
  bool set(double linear, double angular, double sim_time);
  /// The command in force at `sim_time`.
  double linear(double sim_time) const { return timedOut(sim_time) ? 0.0 : linear_; }
  double angular(double sim_time) const { return timedOut(sim_time) ? 0.0 : angular_; }
  void reset() { linear_ = angular_ = command_time_ = 0; }

 private:
  bool timedOut(double sim_time) const { return timeout_ > 0 && sim_time - command_time_ > timeout_; }

  double timeout_;
  double linear_ = 0;
  double angular_ = 0;
  double command_time_ = 0;
};

/// Gazebo's "world" odometry source: the pose of `base_frame` in the world, and its velocities in its own
/// frame.
void setGroundTruth(Odometry& odometry, const RobotBody& body, const std::string& base_frame, double stamp);

}  // namespace bullet_sim
