// The node's ~record: a BagRecorder fed after every step, its robots named as the node names them, and the
// commands their inputs receive, recorded as they arrive between steps.
//
// Params: ~record ["": none; FILE.bag, a relative path taken under $ROS_HOME], ~record_topics [every topic
//   but images and point clouds: a list of regular expressions matching whole topic names, or one],
//   ~record_compression [lz4; none, bz2], ~record_chunk_size [786432 bytes, before compression],
//   ~record_ground_truth_rate [50 Hz of sim time].
#pragma once

#include <ros/ros.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bag_recorder.h"

namespace bullet_sim {

/// Where ~record's FILE goes: an absolute path as it is, a relative one under $ROS_HOME (default ~/.ros).
std::string recordPath(const std::string& file);

class NodeRecording {
 public:
  /// The recording ~record asks for; nullptr when it is empty. Throws std::runtime_error naming a bad
  /// ~record_* parameter. `sim_time` is when a command arrives.
  static std::unique_ptr<NodeRecording> fromParameters(const ros::NodeHandle& private_node,
                                                       std::function<double()> sim_time);
  NodeRecording(const BagSettings& settings, std::function<double()> sim_time);

  /// Records a robot spawned with `robot_namespace` (spawn_model's; "" keeps its plugins' own).
  void addRobot(const Robot& robot, const std::string& robot_namespace);
  void removeRobot(const std::string& name);
  /// After each step, once the adapters have published.
  void afterStep(const Simulation& simulation);
  /// After reset_simulation: the bag is closed and FILE_1.bag begun.
  void restart() { recorder_.restart(); }

 private:
  struct Commands {
    const Robot* robot;
    std::vector<uint64_t> revisions;  ///< of its plugins' port groups, when subscribed
    std::map<std::string, ros::Subscriber> subscribers;  ///< by topic
  };
  /// Subscribes to the robot's command topics that came, and drops those that went.
  void subscribeCommands(Commands& commands);

  BagRecorder recorder_;
  std::function<double()> sim_time_;
  std::map<std::string, Commands> commands_;  ///< by robot
};

}  // namespace bullet_sim
