#include "plugins/ros_control/diff_drive_odometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bullet_sim {

SpeedLimiter SpeedLimiter::fromParameters(const ParameterTree& parameters, const std::string& group) {
  const auto limit = [&](const std::string& name, double fallback) {
    const double value = parameters.number(name, fallback);
    if (std::isnan(value)) {
      throw std::invalid_argument(group + (group.empty() ? "" : "/") + name + " must be a number, not " +
                                  parameters.describe(name));
    }
    return value;
  };
  SpeedLimiter limiter;
  limiter.has_velocity_limits = parameters.flag("has_velocity_limits", false);
  limiter.has_acceleration_limits = parameters.flag("has_acceleration_limits", false);
  limiter.has_jerk_limits = parameters.flag("has_jerk_limits", false);
  limiter.max_velocity = limit("max_velocity", 0);
  limiter.min_velocity = limit("min_velocity", -limiter.max_velocity);
  limiter.max_acceleration = limit("max_acceleration", 0);
  limiter.min_acceleration = limit("min_acceleration", -limiter.max_acceleration);
  limiter.max_jerk = limit("max_jerk", 0);
  limiter.min_jerk = limit("min_jerk", -limiter.max_jerk);
  return limiter;
}

double SpeedLimiter::limit(double v, double v0, double v1, double dt) const {
  // std::clamp's bounds must be ordered; ros_controllers' clamp takes the upper one when they are not.
  const auto clamp = [](double x, double low, double high) { return std::min(std::max(low, x), high); };
  if (has_jerk_limits) {
    const double dv0 = v0 - v1;
    const double dt2 = 2 * dt * dt;
    v = v0 + dv0 + clamp((v - v0) - dv0, min_jerk * dt2, max_jerk * dt2);
  }
  if (has_acceleration_limits) v = v0 + clamp(v - v0, min_acceleration * dt, max_acceleration * dt);
  if (has_velocity_limits) v = clamp(v, min_velocity, max_velocity);
  return v;
}

void DiffDriveOdometry::setWheelParams(double separation, double left_radius, double right_radius) {
  separation_ = separation;
  left_radius_ = left_radius;
  right_radius_ = right_radius;
}

void DiffDriveOdometry::init(double time) {
  linear_samples_.clear();
  angular_samples_.clear();
  linear_sum_ = angular_sum_ = 0;
  time_ = time;
}

void DiffDriveOdometry::update(double left_position, double right_position, double time) {
  const double left = left_position * left_radius_;
  const double right = right_position * right_radius_;
  const double left_step = primed_ ? left - left_travel_ : 0.0;
  const double right_step = primed_ ? right - right_travel_ : 0.0;
  left_travel_ = left;
  right_travel_ = right;
  primed_ = true;
  const double distance = (right_step + left_step) * 0.5;
  const double turn = (right_step - left_step) / separation_;
  integrate(distance, turn);
  const double dt = time - time_;
  if (dt < 0.0001) return;  // too short to take a velocity from
  time_ = time;
  linear_ = rollingMean(linear_samples_, linear_sum_, distance / dt);
  angular_ = rollingMean(angular_samples_, angular_sum_, turn / dt);
}

void DiffDriveOdometry::updateOpenLoop(double linear, double angular, double time) {
  linear_ = linear;
  angular_ = angular;
  const double dt = time - time_;
  time_ = time;
  integrate(linear * dt, angular * dt);
}

void DiffDriveOdometry::resetPose() {
  x_ = y_ = heading_ = linear_ = angular_ = 0;
  primed_ = false;
}

void DiffDriveOdometry::integrate(double distance, double turn) {
  if (std::abs(turn) < 1e-6) {  // second-order Runge-Kutta along a nearly straight path
    const double direction = heading_ + turn * 0.5;
    x_ += distance * std::cos(direction);
    y_ += distance * std::sin(direction);
    heading_ += turn;
    return;
  }
  const double heading = heading_;
  const double radius = distance / turn;
  heading_ += turn;
  x_ += radius * (std::sin(heading_) - std::sin(heading));
  y_ += -radius * (std::cos(heading_) - std::cos(heading));
}

double DiffDriveOdometry::rollingMean(std::deque<double>& samples, double& sum, double sample) const {
  samples.push_back(sample);
  sum += sample;
  while (samples.size() > std::max<size_t>(window_, 1)) {
    sum -= samples.front();
    samples.pop_front();
  }
  return sum / static_cast<double>(samples.size());
}

}  // namespace bullet_sim
