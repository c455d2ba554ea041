// diff_drive_controller's odometry and speed limiter (ros_controllers, Noetic), ROS-free: time is an
// argument.
#pragma once

#include <cstddef>
#include <deque>
#include <string>

#include "bullet_sim/plugins/parameter_tree.h"

namespace bullet_sim {

/// The limits of one command, linear/x or angular/z, under diff_drive_controller's names:
/// has_velocity_limits, max_velocity, min_velocity (default -max_velocity), and the same for acceleration and
/// jerk.
struct SpeedLimiter {
  bool has_velocity_limits = false;
  bool has_acceleration_limits = false;
  bool has_jerk_limits = false;
  double min_velocity = 0, max_velocity = 0;          ///< [m/s] or [rad/s]
  double min_acceleration = 0, max_acceleration = 0;  ///< [m/s^2] or [rad/s^2]
  double min_jerk = 0, max_jerk = 0;                  ///< [m/s^3] or [rad/s^3]

  /// Read from `parameters` (the controller's `group`, linear/x or angular/z). Throws std::invalid_argument
  /// naming a limit that is not a number (NaN would make every command NaN); an infinite one is no limit.
  static SpeedLimiter fromParameters(const ParameterTree& parameters, const std::string& group = "");

  /// `v` limited by jerk, then acceleration, then velocity, after the last two commands `v0` (one period ago)
  /// and `v1` (two), `dt` [s] apart.
  double limit(double v, double v0, double v1, double dt) const;
};

/// A differential drive's pose [m, m, rad] and velocities [m/s, rad/s] from its wheels' positions, integrated
/// exactly along arcs; the velocities are rolling means over the last few updates.
class DiffDriveOdometry {
 public:
  explicit DiffDriveOdometry(size_t velocity_rolling_window_size = 10)
      : window_(velocity_rolling_window_size) {}

  /// [m]: the (multiplied) wheel separation and radii.
  void setWheelParams(double separation, double left_radius, double right_radius);
  /// Starts timing at `time` [s] and forgets the velocity window.
  void init(double time);
  /// Advances by the wheels' travel since the last update: positions [rad] are the mean of each side's
  /// wheels. The first update after construction or resetPose() only takes the positions in.
  void update(double left_position, double right_position, double time);
  /// Advances by a command followed since the last update (open_loop).
  void updateOpenLoop(double linear, double angular, double time);
  /// Back to the origin (a world reset).
  void resetPose();

  double x() const { return x_; }
  double y() const { return y_; }
  double heading() const { return heading_; }
  double linear() const { return linear_; }
  double angular() const { return angular_; }

 private:
  /// Moves the pose by `distance` [m] while turning by `turn` [rad], along the arc they make.
  void integrate(double distance, double turn);
  /// The mean of the last window_ samples, `sample` the newest; `sum` is theirs, kept as they come and go.
  double rollingMean(std::deque<double>& samples, double& sum, double sample) const;

  size_t window_;
  double separation_ = 0, left_radius_ = 0, right_radius_ = 0;
  double time_ = 0;
  double x_ = 0, y_ = 0, heading_ = 0;
  double linear_ = 0, angular_ = 0;
  bool primed_ = false;  ///< the wheel positions below are known
  double left_travel_ = 0, right_travel_ = 0;  ///< [m] at the last update
  std::deque<double> linear_samples_, angular_samples_;
  double linear_sum_ = 0, angular_sum_ = 0;
};

}  // namespace bullet_sim
