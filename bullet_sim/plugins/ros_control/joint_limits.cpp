#include "plugins/ros_control/joint_limits.h"

#include <algorithm>
#include <cmath>

namespace bullet_sim {

namespace {

constexpr double kUnbounded = std::numeric_limits<double>::max();

/// Reads one has_<name>_limits flag and, when it is true, `value` beside it: unset when the flag is false,
/// left as it was when the flag is absent, as joint_limits_rosparam.h does.
void readLimit(const ParameterTree& parameters, const std::string& name, const std::string& value, bool* has,
               double* limit) {
  const std::string flag = "has_" + name + "_limits";
  if (!parameters.has(flag)) return;
  if (!parameters.flag(flag, false)) {
    *has = false;
  } else if (parameters.has(value)) {
    *has = true;
    *limit = parameters.number(value, *limit);
  }
}

}  // namespace

bool JointLimits::fromUrdf(const JointSpec& joint, JointLimits* limits) {
  const bool bounded = joint.type == JointSpec::Type::kRevolute || joint.type == JointSpec::Type::kPrismatic;
  if (!bounded && joint.velocity <= 0 && joint.effort <= 0) return false;
  limits->has_position_limits = bounded;
  if (bounded) {
    limits->min_position = joint.lower;
    limits->max_position = joint.upper;
  }
  limits->angle_wraparound = joint.type == JointSpec::Type::kContinuous;
  limits->has_velocity_limits = joint.velocity > 0;
  limits->max_velocity = joint.velocity;
  limits->has_acceleration_limits = false;
  limits->has_effort_limits = joint.effort > 0;
  limits->max_effort = joint.effort;
  return true;
}

bool JointLimits::fromParameters(const ParameterTree& parameters, JointLimits* limits) {
  if (parameters.keys().empty()) return false;
  if (parameters.has("has_position_limits")) {
    const bool has = parameters.flag("has_position_limits", false);
    if (!has) {
      limits->has_position_limits = false;
      limits->angle_wraparound = parameters.flag("angle_wraparound", limits->angle_wraparound);
    } else if (parameters.has("min_position") && parameters.has("max_position")) {
      limits->has_position_limits = true;
      limits->min_position = parameters.number("min_position", 0);
      limits->max_position = parameters.number("max_position", 0);
    }
  }
  readLimit(parameters, "velocity", "max_velocity", &limits->has_velocity_limits, &limits->max_velocity);
  readLimit(parameters, "acceleration", "max_acceleration", &limits->has_acceleration_limits,
            &limits->max_acceleration);
  readLimit(parameters, "jerk", "max_jerk", &limits->has_jerk_limits, &limits->max_jerk);
  readLimit(parameters, "effort", "max_effort", &limits->has_effort_limits, &limits->max_effort);
  return true;
}

double JointSaturation::clip(double command, double position, double velocity, double dt) {
  switch (interface_) {
    case JointInterface::kPosition:
      return clipPosition(command, position, dt);
    case JointInterface::kVelocity:
      return clipVelocity(command, dt);
    case JointInterface::kEffort:
      return clipEffort(command, position, velocity);
  }
  return command;
}

void JointSaturation::reset() { last_ = std::numeric_limits<double>::quiet_NaN(); }

namespace {

/// `command` within [low, high] and, when `rate_limited`, within `step` of `last`. Bounds that cross give the
/// upper one, as joint_limits_interface's saturate does.
double saturate(double command, double low, double high, bool rate_limited, double last, double step) {
  if (rate_limited) {
    low = std::max(last - step, low);
    high = std::min(last + step, high);
  }
  return std::clamp(command, std::min(low, high), high);
}

}  // namespace

double JointSaturation::clipPosition(double command, double position, double dt) {
  if (std::isnan(last_)) last_ = position;
  const bool bounded = limits_.has_position_limits;
  last_ = saturate(command, bounded ? limits_.min_position : -kUnbounded,
                   bounded ? limits_.max_position : kUnbounded, limits_.has_velocity_limits, last_,
                   limits_.max_velocity * dt);
  return last_;
}

double JointSaturation::clipVelocity(double command, double dt) {
  const bool bounded = limits_.has_velocity_limits;
  last_ = saturate(command, bounded ? -limits_.max_velocity : -kUnbounded,
                   bounded ? limits_.max_velocity : kUnbounded, limits_.has_acceleration_limits,
                   std::isnan(last_) ? 0.0 : last_, limits_.max_acceleration * dt);
  return last_;
}

double JointSaturation::clipEffort(double command, double position, double velocity) const {
  double low = -limits_.effortBound(), high = limits_.effortBound();
  if (limits_.has_position_limits) {
    if (position < limits_.min_position) low = 0;
    if (position > limits_.max_position) high = 0;
  }
  if (limits_.has_velocity_limits) {
    if (velocity < -limits_.max_velocity) low = 0;
    if (velocity > limits_.max_velocity) high = 0;
  }
  return std::clamp(command, low, high);
}

}  // namespace bullet_sim
