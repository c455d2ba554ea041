// ackermann_joint_commander: cmd_vel (geometry_msgs/Twist) for a car-like robot driven through ros_control,
// as the real Tianracer is: each Twist becomes the commands (std_msgs/Float64) of two steering position
// controllers and four wheel velocity controllers, by the Ackermann geometry the robot description gives,
// exactly as libgazebo_ros_ackermann_drive.so steers and drives (ackermann_drive.h). Debian has no
// ackermann_msgs, so it takes cmd_vel.
//
// Private parameters:
//   robot_description [robot_description]  the parameter holding the URDF
//   robot_base_frame [base_footprint]
//   left_steering_joint right_steering_joint front_left_joint front_right_joint rear_left_joint
//     rear_right_joint  the joints, required (the Ackermann plugin's tags)
//   left_steering_controller right_steering_controller front_left_controller front_right_controller
//     rear_left_controller rear_right_controller  the controllers, required: commands go to
//     <controller>/command
//   max_steer [0.6 rad], max_speed [20 m/s]  as the plugin's tags
// A parameter of the wrong type ends it, naming the value (ros_parameters.h).
#include <geometry_msgs/Twist.h>
#include <ros/ros.h>
#include <std_msgs/Float64.h>

#include <array>
#include <stdexcept>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/assets/package_resolver.h"
#include "plugins/ackermann_drive/ackermann_drive.h"
#include "ros_parameters.h"
#include "bullet_sim/plugins/registry.h"

namespace {

using bullet_sim::AckermannConfig;

constexpr std::array<const char*, 6> kWheels = {"left_steering", "right_steering", "front_left",
                                                "front_right",   "rear_left",      "rear_right"};

std::string required(const ros::NodeHandle& parameters, const std::string& name) {
  const std::string value = bullet_sim::textParam(parameters, name, "");
  if (value.empty())
    throw std::runtime_error("~" + name + " is not set: name the joints and controllers it drives");
  return value;
}

/// The joints' names and limits from the parameters, their geometry from the robot description.
AckermannConfig readConfig(const ros::NodeHandle& parameters) {
  AckermannConfig config;
  config.left_steering_joint = required(parameters, "left_steering_joint");
  config.right_steering_joint = required(parameters, "right_steering_joint");
  config.front_left_joint = required(parameters, "front_left_joint");
  config.front_right_joint = required(parameters, "front_right_joint");
  config.rear_left_joint = required(parameters, "rear_left_joint");
  config.rear_right_joint = required(parameters, "rear_right_joint");
  config.robot_base_frame = bullet_sim::textParam(parameters, "robot_base_frame", "base_footprint");
  config.max_steer = bullet_sim::numberParam(parameters, "max_steer", 0.6);
  config.max_speed = bullet_sim::numberParam(parameters, "max_speed", 20.0);
  const std::string description =
      bullet_sim::textParam(parameters, "robot_description", "robot_description");
  std::string urdf;
  if (!ros::param::get(description, urdf))
    throw std::runtime_error("no robot description on [" + description + "]");
  const bullet_sim::ModelSpec model =
      bullet_sim::parseModel(urdf, description, bullet_sim::PackageResolver::fromEnvironment());
  bullet_sim::Diagnostics diagnostics(description);
  bullet_sim::readAckermannGeometry(model, "", config, diagnostics);
  diagnostics.throwIfErrors();
  return config;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "ackermann_joint_commander");
  ros::NodeHandle node, parameters("~");
  try {
    const AckermannConfig config = readConfig(parameters);
    std::array<ros::Publisher, 6> commands;
    for (size_t i = 0; i < kWheels.size(); ++i) {
      const std::string controller = required(parameters, std::string(kWheels[i]) + "_controller");
      commands[i] = node.advertise<std_msgs::Float64>(controller + "/command", 1);
    }
    ROS_INFO("ackermann_joint_commander: wheelbase %.4f m, steering track %.4f m, wheel radius %.4f m",
             config.geometry.wheelbase, config.geometry.steering_track, config.geometry.wheel_radius);
    const ros::Subscriber subscriber =
        node.subscribe<geometry_msgs::Twist>("cmd_vel", 1, [&](const geometry_msgs::Twist::ConstPtr& twist) {
          if (!std::isfinite(twist->linear.x) || !std::isfinite(twist->angular.z)) {
            ROS_WARN_THROTTLE(1, "ackermann_joint_commander: a cmd_vel that is not a number: ignored");
            return;
          }
          const auto wanted = bullet_sim::ackermannJointCommands(config, twist->linear.x, twist->angular.z);
          const std::array<double, 6> values = {wanted.left_steering, wanted.right_steering,
                                                wanted.front_left,    wanted.front_right,
                                                wanted.rear_left,     wanted.rear_right};
          for (size_t i = 0; i < values.size(); ++i) {
            std_msgs::Float64 message;
            message.data = values[i];
            commands[i].publish(message);
          }
        });
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("ackermann_joint_commander: %s", e.what());
    return 1;
  }
  return 0;
}
