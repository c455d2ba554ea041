// Gazebo's DefaultRobotHWSim (gazebo_ros_control, Noetic), ROS-free: the joints ros_control drives, each
// through the interface its transmission names. Their state is read each control period; their commands are
// written every step, clipped to the joint's limits first (joint_limits_interface's saturation):
//   effort:   pushed with the command (0 during an e-stop);
//   velocity: a velocity motor as strong as the effort limit (held at 0 during an e-stop);
//   position: held at the command (where it was when an e-stop began; where it was spawned until the first
//             command, where Gazebo snaps it to 0);
//   with gazebo_ros_control/pid_gains/<joint> (p, i, d, i_clamp, ...) a velocity or position joint is pushed
//   by a PID loop on its velocity or position instead, within the effort limit.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/plugins/parameter_tree.h"
#include "bullet_sim/physics/robot_body.h"
#include "plugins/ros_control/joint_limits.h"
#include "plugins/ros_control/pid.h"

namespace bullet_sim {

/// A joint with a transmission, and the interface ros_control drives it through.
struct DrivenJoint {
  std::string name;
  JointInterface interface = JointInterface::kVelocity;
};

/// "hardware_interface::VelocityJointInterface", ...: the names controller_manager lists claims under.
std::string interfaceName(JointInterface interface);

/// A joint as ros_control's controllers see it: its state and its command.
struct HardwareJoint {
  std::string name;
  JointInterface interface = JointInterface::kVelocity;
  const JointSpec* spec = nullptr;  ///< its URDF joint
  double position = 0;              ///< [rad] or [m], read each control period
  double velocity = 0;              ///< [rad/s] or [m/s]
  double effort = 0;                ///< [N m] or [N]
  double command = 0;               ///< by interface: [N m] or [N], [rad/s] or [m/s], [rad] or [m]
};

class RobotHardware {
 public:
  /// `robot_parameters` is the robot namespace's: its gazebo_ros_control/pid_gains and joint_limits are read
  /// here. Throws SpecError for a parameter of the wrong kind; what Gazebo would ignore goes to `warnings`.
  RobotHardware(const std::vector<DrivenJoint>& joints, const RobotBody& body,
                const ParameterTree& robot_parameters, std::vector<std::string>* warnings);

  std::vector<HardwareJoint>& joints() { return joints_; }
  const std::vector<HardwareJoint>& joints() const { return joints_; }
  /// The joint named `name`, or nullptr.
  HardwareJoint* find(const std::string& name);
  /// The names of the joints driven through `interface`, for messages.
  std::vector<std::string> namesOf(JointInterface interface) const;

  /// Reads every joint's state (DefaultRobotHWSim::readSim).
  void read(const RobotBody& body);
  /// Applies every joint's command, `dt` [s] after the last time (DefaultRobotHWSim::writeSim).
  void write(RobotBody& body, double dt, bool e_stop);
  /// Commands back to as at spawn, and the PID loops and limits too.
  void reset();

 private:
  /// How a joint is driven, beyond what controllers see of it.
  struct Drive {
    int index = -1;  ///< in the RobotBody
    JointLimits limits;
    std::optional<JointSaturation> saturation;  ///< when the joint has limits
    std::optional<Pid> pid;                     ///< for a velocity or position joint with pid_gains
    double hold = 0;                            ///< where a position joint stays during an e-stop
  };

  /// The effort a PID joint is pushed with.
  double pidEffort(const HardwareJoint& joint, Drive& drive, double dt, bool e_stop);

  std::vector<HardwareJoint> joints_;
  std::vector<Drive> drives_;
  bool e_stopped_ = false;
  bool primed_ = false;  ///< the position joints' commands start where the joints are
};

}  // namespace bullet_sim
