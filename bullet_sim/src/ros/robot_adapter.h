// The ROS face of one spawned robot: subscribes its plugins' command topics and publishes their outputs,
// in the robot's namespace and with its frame prefix. Runs between steps, on the node's thread.
#pragma once

#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/simulation.h"

namespace bullet_sim {

class RobotAdapter {
 public:
  /// `robot_namespace` from the spawn request overrides every plugin's <robotNamespace> when it is not empty.
  /// `sim_time` tells when a command arrived.
  RobotAdapter(Robot& robot, const std::string& robot_namespace, tf2_ros::TransformBroadcaster& tf,
               std::function<double()> sim_time);

  /// Publishes what the plugins produced since the last call.
  void publish();

  /// The topics this robot advertises and subscribes, for the log.
  const std::vector<std::string>& topics() const { return topics_; }

 private:
  struct Output {
    std::function<uint64_t()> count;  ///< changes when the plugin has a new output
    std::function<void()> publish;
    uint64_t seen = 0;
  };
  /// What a drive plugin's cmd_vel, odometry and odom tf need from its config.
  struct DriveTopics {
    std::string robot_namespace;
    std::string command_topic;
    std::string odometry_topic;
    std::string odometry_frame;
    std::string robot_base_frame;
    bool publish_odometry;
    bool publish_odom_tf;
  };

  /// Subscribes a drive (WheeledDrive, AckermannDrive) to its cmd_vel and publishes its odometry and odom
  /// tf. Returns the node handle of its namespace.
  template <class Drive>
  ros::NodeHandle connectDrive(Drive* drive, const DriveTopics& topics);
  ros::NodeHandle handleFor(const std::string& plugin_namespace) const;
  std::string frame(const std::string& name) const;
  template <class Message>
  ros::Publisher advertise(ros::NodeHandle handle, const std::string& topic);

  Robot& robot_;
  std::string namespace_;
  std::string frame_prefix_;
  tf2_ros::TransformBroadcaster& tf_;
  std::function<double()> sim_time_;
  std::vector<ros::Publisher> publishers_;
  std::vector<ros::Subscriber> subscribers_;
  std::vector<Output> outputs_;
  std::vector<std::string> topics_;
};

}  // namespace bullet_sim
