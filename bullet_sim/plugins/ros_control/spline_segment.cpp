#include "plugins/ros_control/spline_segment.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace bullet_sim {

namespace {

bool finite(const Knot& knot) {
  return std::isfinite(knot.position) && std::isfinite(knot.velocity.value_or(0)) &&
         std::isfinite(knot.acceleration.value_or(0));
}

}  // namespace

SplineSegment::SplineSegment(double start_time, const Knot& start, double end_time, const Knot& end)
    : start_time_(start_time), duration_(end_time - start_time) {
  if (!std::isfinite(start_time) || !std::isfinite(end_time) || !finite(start) || !finite(end))
    throw std::invalid_argument("a trajectory segment with a figure that is not a number");
  if (end_time < start_time) {
    throw std::invalid_argument("a trajectory segment that ends (" + std::to_string(end_time) +
                                " s) before it starts (" + std::to_string(start_time) + " s)");
  }
  const double p0 = start.position, p1 = end.position, T = duration_;
  auto& c = coefficients_;
  c[0] = p0;
  if (!start.velocity || !end.velocity) {
    order_ = Order::kLinear;
    c[1] = T == 0 ? 0 : (p1 - p0) / T;
    return;
  }
  const double v0 = *start.velocity, v1 = *end.velocity;
  c[1] = v0;
  if (!start.acceleration || !end.acceleration) {
    order_ = Order::kCubic;
    if (T == 0) return;
    c[2] = (3 * (p1 - p0) - (2 * v0 + v1) * T) / (T * T);
    c[3] = (2 * (p0 - p1) + (v0 + v1) * T) / (T * T * T);
    return;
  }
  order_ = Order::kQuintic;
  const double a0 = *start.acceleration, a1 = *end.acceleration;
  c[2] = a0 / 2;
  if (T == 0) return;
  const double T2 = T * T, T3 = T2 * T;
  c[3] = (20 * (p1 - p0) - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T2) / (2 * T3);
  c[4] = (30 * (p0 - p1) + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T2) / (2 * T3 * T);
  c[5] = (12 * (p1 - p0) - 6 * (v1 + v0) * T - (a0 - a1) * T2) / (2 * T3 * T2);
}

JointMotion SplineSegment::evaluate(double t) const {
  const auto& c = coefficients_;
  JointMotion motion;
  motion.position = c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * (c[4] + t * c[5]))));
  motion.velocity = c[1] + t * (2 * c[2] + t * (3 * c[3] + t * (4 * c[4] + t * 5 * c[5])));
  motion.acceleration = 2 * c[2] + t * (6 * c[3] + t * (12 * c[4] + t * 20 * c[5]));
  return motion;
}

JointMotion SplineSegment::sample(double time) const {
  const double t = time - start_time_;
  if (t < 0) return {evaluate(0).position, 0, 0};
  if (t > duration_) return {evaluate(duration_).position, 0, 0};
  return evaluate(t);
}

}  // namespace bullet_sim
