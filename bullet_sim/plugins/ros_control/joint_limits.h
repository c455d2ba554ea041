// A joint's limits as joint_limits_interface (Noetic) reads and enforces them for Gazebo's DefaultRobotHWSim:
// the URDF's <limit> first, then the joint_limits/<joint> parameters over it; the saturation handles clip
// each command before it reaches the joint.
#pragma once

#include <limits>

#include "bullet_sim/model/model.h"
#include "bullet_sim/plugins/parameter_tree.h"

namespace bullet_sim {

/// ros_control's three joint command interfaces.
enum class JointInterface { kEffort, kVelocity, kPosition };

struct JointLimits {
  bool has_position_limits = false;
  double min_position = 0, max_position = 0;  ///< [rad] or [m]
  bool has_velocity_limits = false;
  double max_velocity = 0;  ///< [rad/s] or [m/s]
  bool has_acceleration_limits = false;
  double max_acceleration = 0;  ///< [rad/s^2] or [m/s^2]
  bool has_jerk_limits = false;  ///< read; no saturation handle enforces jerk
  double max_jerk = 0;
  bool has_effort_limits = false;
  double max_effort = 0;  ///< [N m] or [N]
  bool angle_wraparound = false;  ///< a continuous joint

  /// The URDF's limits, as joint_limits_urdf.h reads them; false when the joint has none (bullet_sim takes a
  /// zero velocity or effort limit as none given).
  static bool fromUrdf(const JointSpec& joint, JointLimits* limits);
  /// Overrides `limits` with joint_limits/<joint> (`parameters` is that subtree): each has_* flag with its
  /// value, as joint_limits_rosparam.h reads them. False when there is no such subtree. Throws SpecError for
  /// a value of the wrong kind.
  static bool fromParameters(const ParameterTree& parameters, JointLimits* limits);

  /// [N m] or [N]: max_effort, or no bound.
  double effortBound() const {
    return has_effort_limits ? max_effort : std::numeric_limits<double>::infinity();
  }
};

/// joint_limits_interface's saturation handle for one joint and interface: clips commands to the limits.
class JointSaturation {
 public:
  JointSaturation(JointInterface interface, const JointLimits& limits)
      : interface_(interface), limits_(limits) {}

  /// The command `command` clipped for a joint at `position` and `velocity`, `dt` [s] after the last one.
  double clip(double command, double position, double velocity, double dt);
  /// Forgets the last command (after an e-stop or a reset).
  void reset();

 private:
  double clipPosition(double command, double position, double dt);
  double clipVelocity(double command, double dt);
  double clipEffort(double command, double position, double velocity) const;

  JointInterface interface_;
  JointLimits limits_;
  double last_ = std::numeric_limits<double>::quiet_NaN();  ///< the last clipped command; NaN: none yet
};

}  // namespace bullet_sim
