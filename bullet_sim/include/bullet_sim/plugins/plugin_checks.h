// A plugin's own checks for urdf_doctor: what in a URDF makes that plugin misbehave without saying so (a
// drive wheel turning backwards, a zero limit on a joint it drives). A plugin type registers its check
// (PluginType::check); the doctor calls the check of every plugin the robot declares and reports what it
// finds. The doctor's own messages are written with the same helpers, so that all read alike. ROS-free.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

/// A fault a plugin's check finds.
struct PluginFinding {
  bool error = true;  ///< false: a warning
  /// The element it is about, e.g. "joint [x] <limit>": when two plugins' checks find a fault in the same
  /// element, the doctor reports the first.
  std::string subject;
  std::string message;  ///< the element, what is wrong, and the fix (checks::message)
};

/// A URDF <limit> that writes effort or velocity as 0 (the model cannot tell a zero from no limit at all).
struct ZeroLimit {
  std::string joint;
  int line = 0;                         ///< of the <limit> in the file
  std::vector<std::string> attributes;  ///< "effort", "velocity" or both, in that order
};

/// What the doctor gives a plugin's check.
struct PluginCheckInput {
  const ModelSpec& model;
  const PluginDeclaration& declaration;
  const std::vector<ZeroLimit>& zero_limits;  ///< every joint's, in the file's order
};

using PluginCheck = std::function<std::vector<PluginFinding>(const PluginCheckInput& input)>;

namespace checks {

/// A number as the doctor writes it: 5 significant digits, and 0 for anything within 1e-9 of it.
std::string number(double value);
/// "x y z", each a number().
std::string vectorText(const Eigen::Vector3d& v);
/// "element: problem. Fix: fix."
std::string message(const std::string& element, const std::string& problem, const std::string& fix);

/// Zero effort or velocity limits on the `motors` a plugin drives, which a motor honouring the URDF limits
/// cannot move; `note` says what the plugin adds about them ("" for nothing).
std::vector<PluginFinding> zeroLimitsOnMotors(const PluginCheckInput& input,
                                              const std::vector<std::string>& motors,
                                              const std::string& note = "");

}  // namespace checks
}  // namespace bullet_sim
