// libgazebo_ros_control.so (gazebo_ros_control, Noetic), ROS-free: ros_control inside the simulator. It
// drives the joints of the URDF's <transmission>s as Gazebo's DefaultRobotHWSim does (robot_hardware.h), and
// serves a controller manager under <robotNamespace>/controller_manager/: load_controller, unload_controller,
// switch_controller, list_controllers, list_controller_types and reload_controller_libraries. Its controllers
// read their parameters from the parameter server and update at the control period, in sim time.
//
// Its tags, Noetic's with their defaults and our wheelModel, are the table rosControlTags() in
// ros_control_plugin.cpp.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"
#include "plugins/ros_control/controller_manager.h"
#include "plugins/ros_control/robot_hardware.h"

namespace bullet_sim {

struct RosControlConfig : PluginConfig {
  bool namespace_given = false;  ///< <robotNamespace> is there (even empty: the root)
  double control_period = 0;     ///< [s]; 0 = every step
  std::string e_stop_topic;   ///< "" = none
  std::string wheel_model;    ///< <wheelModel>; "" = by the rule
  std::vector<DrivenJoint> joints;  ///< from the transmissions, in the file's order
};

/// Reads the tags and the model's transmissions: a transmission naming a joint the robot does not have, or an
/// interface DefaultRobotHWSim does not simulate, is an error; what ros_control skips is a warning.
void parseRosControl(const DeclarationSource& source, RosControlConfig& config);

/// Where ros_control lives for a robot: the spawn's -robot_namespace, else <robotNamespace>, else the model's
/// name (`robot_name`), as in Noetic.
std::string rosControlNamespace(const RosControlConfig& config, const std::string& robot_name,
                                const std::optional<std::string>& spawn_namespace);

/// The wheel model of a robot driven through ros_control. Its wheels are the joints a
/// diff_drive_controller/DiffDriveController in its parameters (`robot_parameters`, its namespace's) names,
/// or else its continuous joints with a velocity or effort transmission. With wheels it gets <wheelModel>,
/// else the drive plugins' default (raycast); without, contact. Raycast moves joints other than wheels
/// kinematically, so a robot that pushes such a joint by effort (an effort transmission, or pid_gains) gets
/// contact, and asking for raycast then is an error in `diagnostics`.
std::string rosControlWheelModel(const RosControlConfig& config, const ModelSpec& model,
                                 const ParameterTree& robot_parameters, Diagnostics& diagnostics);

class RosControl : public Plugin {
 public:
  RosControl(const PluginDeclaration& declaration, const RosControlConfig& config, const PluginSetup& setup);

  void applyCommands(const StepTime& time, RobotBody& body) override;
  /// Controllers started since the last update take the joints' new positions as their hold point.
  std::vector<std::string> jointsPlaced(const RobotBody& body) override;
  /// switch_controller: the controllers it starts see the joints where they are now, as in Gazebo, whose
  /// controller manager starts them in its update, after reading the joints.
  std::string switchControllers(const SwitchControllerRequest& request, std::vector<std::string>* warnings);
  std::vector<PortGroup> portGroups() const override { return manager_->portGroups(); }
  uint64_t portGroupsRevision() const override { return manager_->revision(); }

  /// For in-process use (tests, tools): what the controller_manager services call.
  ControllerManager& controllerManager() { return *manager_; }
  const RobotHardware& hardware() const { return *hardware_; }

 private:
  void onReset() override;
  void serveControllerManager();

  const RobotBody& body_;
  std::unique_ptr<RobotHardware> hardware_;
  std::unique_ptr<ControllerManager> manager_;
  double now_ = 0;          ///< [s] the end of the last step
  double last_update_ = 0;  ///< [s] of the last controller update
  bool e_stop_ = false;
  bool was_e_stopped_ = false;
  bool restart_pending_ = false;  ///< after a reset, the controllers restart at the next step
};

}  // namespace bullet_sim
