// One joint's motion between two waypoints, as ros_controllers' QuinticSplineSegment
// (joint_trajectory_controller, Noetic) interpolates it: by what the waypoints give, a line through the
// positions, a cubic through the positions and velocities, or a quintic through the positions, velocities and
// accelerations. When the two waypoints give different things, the least they have in common is used.
#pragma once

#include <array>
#include <optional>

namespace bullet_sim {

/// Where a joint is at one waypoint, and as much of how it moves there as the waypoint says.
struct Knot {
  double position = 0;                 ///< [rad] or [m]
  std::optional<double> velocity;      ///< [rad/s] or [m/s]
  std::optional<double> acceleration;  ///< [rad/s^2] or [m/s^2]; used only with a velocity
};

/// A joint's position, velocity and acceleration at one time.
struct JointMotion {
  double position = 0;
  double velocity = 0;
  double acceleration = 0;
};

class SplineSegment {
 public:
  enum class Order { kLinear, kCubic, kQuintic };

  /// A segment that holds position 0 at time 0.
  SplineSegment() = default;
  /// From `start` at `start_time` to `end` at `end_time` [s]. Throws std::invalid_argument when end_time is
  /// before start_time, or a figure is not finite. A segment of no duration holds the start.
  SplineSegment(double start_time, const Knot& start, double end_time, const Knot& end);

  /// The motion at `time` [s]. Before the segment it is the start position at rest, after it the end position
  /// at rest, as ros_controllers samples it.
  JointMotion sample(double time) const;

  double startTime() const { return start_time_; }
  double endTime() const { return start_time_ + duration_; }
  Order order() const { return order_; }

 private:
  /// The polynomial and its derivatives at `t` [s] after the start.
  JointMotion evaluate(double t) const;

  std::array<double, 6> coefficients_{};  ///< of t^0 .. t^5
  double start_time_ = 0;
  double duration_ = 0;
  Order order_ = Order::kLinear;
};

}  // namespace bullet_sim
