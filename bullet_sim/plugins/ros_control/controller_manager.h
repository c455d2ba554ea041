// ros_control's controller manager (Noetic), ROS-free: it loads controllers by type name from their
// parameters (<robot namespace>/<name>/type, ...), starts and stops them as switch_controller asks (STRICT
// or BEST_EFFORT, no two running controllers claiming one joint), updates the running ones at the control
// period and unloads them. Requests are answered at once, between steps: a switch takes effect before the
// next update.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/plugins/parameter_tree.h"
#include "bullet_sim/plugins/ports.h"
#include "plugins/ros_control/controller.h"
#include "plugins/ros_control/robot_hardware.h"

namespace bullet_sim {

class ControllerRegistry;

class ControllerManager {
 public:
  /// Controllers' parameters come from `parameters` (nullptr: none) under `robot_namespace`.
  ControllerManager(RobotHardware& hardware, const ControllerRegistry& types,
                    const ParameterSource* parameters, std::string robot_namespace, const ModelSpec& model);
  ~ControllerManager();

  // The services, each answering "" when done, else why not.
  std::string load(const std::string& name, std::vector<std::string>* warnings);
  std::string unload(const std::string& name);
  /// Stops, then starts, at `time` [s].
  std::string switchControllers(const SwitchControllerRequest& request, double time,
                                std::vector<std::string>* warnings);
  std::vector<ControllerStatus> list() const;
  ListControllerTypesRequest::Reply listTypes() const;
  /// Controllers are built in, so there is nothing to reload: it succeeds once no controller is loaded (with
  /// force_kill, after stopping and unloading them all).
  std::string reloadLibraries(bool force_kill, double time);

  /// Updates the running controllers; with `restart_running` (an e-stop released) they stop and start first.
  void update(double time, double period, bool restart_running);
  /// After a world reset: every controller forgets what it integrated; the running ones start again.
  void restart(double time);
  /// The joints were put somewhere from outside the physics (set_model_configuration) after the running
  /// controllers that have not updated yet started: those stop and start again at `time`, as controllers
  /// started now would, to hold the joints where they are now (Gazebo starts them at its next update, after
  /// reading the joints). Returns a warning for each that drops what it was following.
  std::vector<std::string> startUnupdatedAgain(double time);

  /// The controller named `name`, or nullptr.
  Controller* find(const std::string& name) const;
  /// Each loaded controller's ports; the revision changes when controllers are loaded or unloaded.
  std::vector<PortGroup> portGroups() const;
  uint64_t revision() const { return revision_; }

 private:
  struct Loaded {
    uint64_t id = 0;
    std::shared_ptr<Controller> controller;
    PluginPorts ports;  ///< the controller's, with inputs that do nothing once it is unloaded
  };
  /// The switch's stop and start lists resolved to loaded controllers; "" or why the switch is refused.
  std::string resolveSwitch(const SwitchControllerRequest& request, int strictness,
                            std::vector<Controller*>* stop, std::vector<Controller*>* start) const;
  /// "" or the resource conflict among the controllers that would run.
  std::string conflict(const std::vector<Controller*>& running) const;
  std::string parameterNamespace(const std::string& name) const;

  RobotHardware& hardware_;
  const ControllerRegistry& types_;
  const ParameterSource* parameters_;
  std::string namespace_;  ///< "/" or "/ns"
  const ModelSpec& model_;
  std::vector<Loaded> controllers_;
  uint64_t next_id_ = 1;
  uint64_t revision_ = 0;
};

}  // namespace bullet_sim
