// control_toolbox's Pid (Noetic), which ros_control's effort controllers and Gazebo's pid_gains use: gains p,
// i, d, i_clamp (or i_clamp_min and i_clamp_max) and antiwindup from the parameter server, the same integral
// clamp and the same derivative of the error.
#pragma once

#include <optional>
#include <string>

#include "bullet_sim/plugins/parameter_tree.h"

namespace bullet_sim {

struct PidGains {
  double p = 0, i = 0, d = 0;
  double i_max = 0;  ///< the integral term's bounds: |i_clamp| and -|i_clamp| (0 and 0: no integral term)
  double i_min = 0;
  bool antiwindup = false;  ///< bound the integrated error rather than the integral term
};

class Pid {
 public:
  explicit Pid(const PidGains& gains) : gains_(gains) {}

  /// The gains under `parameters` (p required; i, d, i_clamp, i_clamp_min, i_clamp_max, antiwindup), or
  /// nullopt when there is no p. Throws SpecError for a value of the wrong kind.
  static std::optional<PidGains> gainsFrom(const ParameterTree& parameters);

  /// The command for `error` after `dt` [s] since the last one; the error's derivative is estimated from the
  /// last error. 0 when dt is 0 or the error is not finite.
  double compute(double error, double dt);
  /// The same with the error's derivative given.
  double compute(double error, double error_dot, double dt);
  /// Forgets the integral and the last error, as ros_control does when a controller starts.
  void reset();

  const PidGains& gains() const { return gains_; }

 private:
  PidGains gains_;
  double last_error_ = 0;
  bool last_error_valid_ = true;  ///< after reset() the derivative is taken from 0, as control_toolbox does
  double error_dot_ = 0;
  double integral_ = 0;  ///< of the error [error s]
};

}  // namespace bullet_sim
