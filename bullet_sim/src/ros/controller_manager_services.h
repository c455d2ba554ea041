// The controller manager's services (controller_manager_msgs) for a plugin's handlers: load_controller,
// unload_controller, switch_controller, list_controllers, list_controller_types and
// reload_controller_libraries. A refused request is logged as ros_control logs it and answered with ok false.
#pragma once

#include <ros/ros.h>

#include <string>

#include "bullet_sim/plugins/ports.h"

namespace bullet_sim {

/// Advertises `name` in `handle` for `handler`, one of the controller manager's request types. `robot` heads
/// the log lines.
ros::ServiceServer serveControllerManager(ros::NodeHandle& handle, const std::string& name,
                                          const ServiceSink& handler, const std::string& robot);

}  // namespace bullet_sim
