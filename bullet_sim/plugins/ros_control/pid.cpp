#include "plugins/ros_control/pid.h"

#include <algorithm>
#include <cmath>

namespace bullet_sim {

std::optional<PidGains> Pid::gainsFrom(const ParameterTree& parameters) {
  if (!parameters.has("p")) return std::nullopt;
  PidGains gains;
  gains.p = parameters.number("p", 0);
  gains.i = parameters.number("i", 0);
  gains.d = parameters.number("d", 0);
  const double clamp = std::abs(parameters.number("i_clamp", 0));
  gains.i_max = std::abs(parameters.number("i_clamp_max", clamp));
  gains.i_min = -std::abs(parameters.number("i_clamp_min", -clamp));
  gains.antiwindup = parameters.flag("antiwindup", false);
  return gains;
}

double Pid::compute(double error, double dt) {
  if (dt == 0 || !std::isfinite(error)) return 0;
  double error_dot = error_dot_;
  if (dt > 0) {
    if (last_error_valid_) error_dot = (error - last_error_) / dt;
    last_error_ = error;
    last_error_valid_ = true;
  }
  return compute(error, error_dot, dt);
}

double Pid::compute(double error, double error_dot, double dt) {
  error_dot_ = error_dot;
  if (dt == 0 || !std::isfinite(error) || !std::isfinite(error_dot)) return 0;
  integral_ += dt * error;
  if (gains_.antiwindup && gains_.i != 0) {
    const double a = gains_.i_min / gains_.i, b = gains_.i_max / gains_.i;
    integral_ = std::clamp(integral_, std::min(a, b), std::max(a, b));
  }
  double i_term = gains_.i * integral_;
  if (!gains_.antiwindup) i_term = std::clamp(i_term, gains_.i_min, gains_.i_max);
  return gains_.p * error + i_term + gains_.d * error_dot;
}

void Pid::reset() {
  last_error_ = 0;
  last_error_valid_ = true;
  error_dot_ = 0;
  integral_ = 0;
}

}  // namespace bullet_sim
