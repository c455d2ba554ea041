// A ros_control controller inside the simulator, ROS-free. The controller manager builds it by type name when
// it is loaded, from its parameters (the parameter server's <robot namespace>/<name>), then starts, updates
// at the control period and stops it as ros_control's ControllerBase does. Its topics live under its name (a
// diff drive controller's <name>/cmd_vel), except what it publishes for the whole robot (joint_states, /tf).
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/model/model.h"
#include "bullet_sim/plugins/parameter_tree.h"
#include "bullet_sim/plugins/ports.h"
#include "plugins/ros_control/robot_hardware.h"

namespace bullet_sim {

/// What ros_control's list_controllers says of a controller.
enum class ControllerState { kInitialized, kRunning, kStopped };

/// "initialized", "running" or "stopped".
std::string stateName(ControllerState state);

/// What a controller is built with.
struct ControllerSetup {
  const std::string& name;
  const std::string& type;
  const ParameterTree& parameters;  ///< its own: <robot namespace>/<name>
  RobotHardware& hardware;
  const ModelSpec& model;  ///< the robot's URDF, for what controllers read from it (wheel geometry)
  std::vector<std::string>& warnings;  ///< about its parameters; the node logs them
};

class Controller {
 public:
  /// It claims joints through `hardware_interface` (ros_control's C++ name, e.g.
  /// hardware_interface::VelocityJointInterface), as list_controllers reports.
  Controller(const ControllerSetup& setup, std::string hardware_interface);
  virtual ~Controller() = default;
  Controller(const Controller&) = delete;
  Controller& operator=(const Controller&) = delete;

  const std::string& name() const { return name_; }
  const std::string& type() const { return type_; }
  ControllerState state() const { return state_; }
  bool running() const { return state_ == ControllerState::kRunning; }
  /// Whether it runs and has not updated since it started.
  bool awaitsFirstUpdate() const { return running() && !updated_; }
  /// What a stop would drop that it is following, for a warning ("" for nothing): a trajectory goal.
  virtual std::string following() const { return ""; }
  const PluginPorts& ports() const { return ports_; }
  const ClaimedResources& claims() const { return claims_; }

  /// ros_control's startRequest, stopRequest and updateRequest: `time` is sim time [s], `period` [s] the time
  /// since the last update.
  void start(double time);
  void stop(double time);
  void update(double time, double period);
  /// After a world reset: what it integrated (odometry) back to as when it was loaded; a running controller
  /// then starts again at `time`.
  void restart(double time);

 protected:
  virtual void starting(double /*time*/) {}
  virtual void stopping(double /*time*/) {}
  virtual void onUpdate(double time, double period) = 0;
  virtual void onReset() {}

  /// The joint `joint`, claimed through this controller's interface. Throws std::invalid_argument naming the
  /// joints there are when no such joint is driven through it.
  HardwareJoint& claim(const std::string& joint, JointInterface interface);
  /// A topic under the controller's name: <name>/<relative>.
  std::string topic(const std::string& relative) const { return name_ + "/" + relative; }
  PluginPorts& ownPorts() { return ports_; }
  RobotHardware& hardware() { return hardware_; }
  /// One warning in `setup` for each of its parameters that is not in `known` (type is always known).
  void warnUnread(const ControllerSetup& setup, const std::vector<std::string>& known) const;

 private:
  std::string name_;
  std::string type_;
  RobotHardware& hardware_;
  ControllerState state_ = ControllerState::kInitialized;
  bool updated_ = false;  ///< since it last started
  PluginPorts ports_;
  ClaimedResources claims_;
};

}  // namespace bullet_sim
