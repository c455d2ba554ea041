#include "bullet_sim/plugins/plugin_checks.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace bullet_sim {
namespace checks {

std::string number(double value) {
  std::ostringstream out;
  out << std::setprecision(5) << (std::abs(value) < 1e-9 ? 0.0 : value);
  return out.str();
}

std::string vectorText(const Eigen::Vector3d& v) {
  return number(v.x()) + " " + number(v.y()) + " " + number(v.z());
}

std::string message(const std::string& element, const std::string& problem, const std::string& fix) {
  return element + ": " + problem + ". Fix: " + fix + ".";
}

std::vector<PluginFinding> zeroLimitsOnMotors(const PluginCheckInput& input,
                                              const std::vector<std::string>& motors,
                                              const std::string& note) {
  std::vector<PluginFinding> found;
  for (const ZeroLimit& limit : input.zero_limits) {
    if (std::find(motors.begin(), motors.end(), limit.joint) == motors.end()) continue;
    const std::string which =
        limit.attributes.size() == 2 ? "effort and velocity are" : limit.attributes.front() + " is";
    const std::string subject = "joint [" + limit.joint + "] <limit>";
    found.push_back(
        {true, subject,
         message("line " + std::to_string(limit.line) + ": " + subject,
                 "its " + which +
                     " 0, yet a plugin drives it: a motor that honours the URDF limits "
                     "(ros_control, Gazebo's SetForce, bullet_sim's joint holder) cannot move it" +
                     (note.empty() ? "" : "; " + note),
                 "give the motor's real figures, e.g. effort=\"0.2\" [N m] velocity=\"5\" [rad/s] for a "
                 "hobby servo")});
  }
  return found;
}

}  // namespace checks
}  // namespace bullet_sim
