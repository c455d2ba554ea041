// One robot as a bag records it: every output of its plugins as the node publishes it (the port groups that
// come and go included), its links' transforms as robot_state_publisher publishes them, and its ground truth.
#pragma once

#include <geometry_msgs/TransformStamped.h>

#include <functional>
#include <map>
#include <regex>
#include <string>
#include <unordered_map>
#include <vector>

#include "bag_writer.h"
#include "bullet_sim/simulation/simulation.h"
#include "messages.h"

namespace bullet_sim {

/// Which topics a bag records: those matching one of the regular expressions (the whole name), or, without
/// any, every topic but camera images and point clouds.
class TopicFilter {
 public:
  /// Throws std::invalid_argument naming an expression that is not one.
  explicit TopicFilter(const std::vector<std::string>& patterns);
  /// Whether `topic` (a full name), of ROS type `type` ("sensor_msgs/Image"), is recorded.
  bool records(const std::string& topic, const std::string& type) const;

 private:
  std::vector<std::regex> patterns_;
};

/// How a robot's topics and frames are named, as the node names them.
struct RobotNames {
  /// replaces its plugins' namespaces when not empty (spawn's -robot_namespace)
  std::string robot_namespace;
  std::function<FramePrefix(const Plugin& plugin)> plugin_frames;  ///< the tf_prefix of a plugin's frames
  FramePrefix link_frames;  ///< robot_state_publisher's tf_prefix
};

/// A topic a robot takes commands on, and the ROS type of its messages.
struct CommandTopic {
  std::string topic;
  std::string type;
};

class RobotRecording {
 public:
  /// Records `robot` (which must outlive this) through `filter`, its ground truth at `ground_truth_rate`
  /// [Hz].
  RobotRecording(const Robot& robot, RobotNames names, const TopicFilter& filter, double ground_truth_rate);

  const std::string& name() const { return name_; }
  /// Writes what its plugins produced since the last call (each sample once, in plugin order), its moving
  /// links' transforms with every joint_states sample, and its ground truth when due.
  void afterStep(const Simulation& simulation, BagWriter& writer);
  /// Its fixed joints as robot_state_publisher puts them on /tf_static, stamped `stamp` [s].
  std::vector<geometry_msgs::TransformStamped> fixedTransforms(double stamp) const;
  /// Its inputs' topics that the filter records, and their types.
  std::vector<CommandTopic> commandTopics() const;
  /// The full name of `topic` of `plugin`; "" when ROS refuses the name.
  std::string topicOf(const Plugin& plugin, const std::string& topic) const;
  /// The full name of `plugin`'s input `topic` when the filter records it, else "".
  std::string commandTopic(const Plugin& plugin, const std::string& topic, const std::string& type) const;
  /// After a reset of the simulation: the ground truth's timer restarts.
  void restart() { ground_truth_timer_.reset(); }

 private:
  /// One output being recorded: how many samples its stream has had, and how to write the latest.
  struct Output {
    std::function<uint64_t()> count;
    std::function<void(BagWriter& writer, double sim_time)> write;
    uint64_t seen = 0;
    Demand* demand = nullptr;  ///< the plugin's, kept wanted (a camera's images, when recorded)
  };
  struct Group {
    const Plugin* plugin;
    uint64_t revision;
  };

  void connect(const Plugin& plugin, const PluginPorts& ports, std::vector<Output>& into) const;
  template <class Sample>
  void connectStream(const Plugin& plugin, const std::string& topic, const Stream<Sample>* stream,
                     Demand* demand, std::vector<Output>& into) const;
  /// Connects the port groups that appeared since the last call and drops those that went.
  void refreshGroups();
  void writeOutputs(std::vector<Output>& outputs, BagWriter& writer, double sim_time);
  /// robot_state_publisher's /tf for the moving joints a joint_states sample names.
  tf2_msgs::TFMessage movingTransforms(const JointStateSample& states) const;
  void writeGroundTruth(BagWriter& writer, double sim_time) const;

  const Robot& robot_;
  const std::string name_;
  const RobotNames names_;
  const TopicFilter& filter_;
  std::string namespace_;  ///< of its ground truth: the robot's namespace, else its first plugin's
  std::unordered_map<std::string, const JointSpec*> moving_joints_;
  UpdateTimer ground_truth_timer_;
  std::vector<Output> outputs_;  ///< of its plugins' own ports
  std::vector<Group> watched_;
  std::map<std::pair<const Plugin*, uint64_t>, std::vector<Output>> groups_;  ///< by plugin and group id
};

}  // namespace bullet_sim
