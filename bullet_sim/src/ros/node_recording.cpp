#include "node_recording.h"

#include <cstdlib>
#include <filesystem>

#include "ros_parameters.h"

namespace bullet_sim {

namespace {

ros::NodeHandle handleIn(const std::string& robot_namespace) {
  const std::string ns = withoutSlashes(robot_namespace);
  return ns.empty() ? ros::NodeHandle() : ros::NodeHandle("/" + ns);
}

/// ~record_topics: a list of regular expressions, or one.
std::vector<std::string> topicPatterns(const ros::NodeHandle& private_node) {
  std::vector<std::string> patterns;
  if (private_node.getParam("record_topics", patterns)) return patterns;
  std::string pattern;
  if (private_node.getParam("record_topics", pattern)) return {pattern};
  if (private_node.hasParam("record_topics"))
    throw std::runtime_error("~record_topics: give a list of regular expressions, or one");
  return {};
}

BagSettings settingsFrom(const ros::NodeHandle& private_node, const std::string& file) {
  BagSettings settings;
  settings.path = recordPath(file);
  settings.topics = topicPatterns(private_node);
  settings.compression = textParam(private_node, "record_compression", settings.compression);
  const int chunk_size = wholeParam(private_node, "record_chunk_size", static_cast<int>(settings.chunk_size));
  if (chunk_size <= 0)
    throw std::runtime_error("~record_chunk_size [" + std::to_string(chunk_size) + "]: give bytes > 0");
  settings.chunk_size = static_cast<uint32_t>(chunk_size);
  settings.ground_truth_rate =
      numberParam(private_node, "record_ground_truth_rate", settings.ground_truth_rate);
  return settings;
}

}  // namespace

std::string recordPath(const std::string& file) {
  if (std::filesystem::path(file).is_absolute()) return file;
  const char* ros_home = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  const std::filesystem::path base =
      ros_home ? ros_home : std::filesystem::path(home ? home : "/tmp") / ".ros";
  return (base / file).string();
}

std::unique_ptr<NodeRecording> NodeRecording::fromParameters(const ros::NodeHandle& private_node,
                                                             std::function<double()> sim_time) {
  const std::string file = textParam(private_node, "record", "");
  if (file.empty()) return nullptr;
  try {
    return std::make_unique<NodeRecording>(settingsFrom(private_node, file), std::move(sim_time));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("~record: ") + e.what());
  }
}

NodeRecording::NodeRecording(const BagSettings& settings, std::function<double()> sim_time)
    : recorder_(settings, [](const std::string& error) { ROS_ERROR("~record: %s", error.c_str()); }),
      sim_time_(std::move(sim_time)) {
  ROS_INFO("recording into %s", recorder_.path().c_str());
}

void NodeRecording::addRobot(const Robot& robot, const std::string& robot_namespace) {
  RobotNames names;
  names.robot_namespace = robot_namespace;
  names.plugin_frames = [robot_namespace](const Plugin& plugin) {
    return framePrefixOf(handleIn(robot_namespace.empty() ? plugin.robotNamespace() : robot_namespace),
                         plugin);
  };
  // robot_state_publisher, in the robot's namespace, searches tf_prefix up from there.
  const std::string ns = robot_namespace.empty() && !robot.plugins().empty()
                             ? robot.plugins()[0]->robotNamespace()
                             : robot_namespace;
  const ros::NodeHandle handle = handleIn(ns);
  std::string key, prefix;
  if (handle.searchParam("tf_prefix", key)) handle.getParam(key, prefix);
  names.link_frames = FramePrefix(prefix);
  recorder_.addRobot(robot, std::move(names));
  Commands& commands = commands_[robot.name()];
  commands.robot = &robot;
  subscribeCommands(commands);
}

void NodeRecording::removeRobot(const std::string& name) {
  commands_.erase(name);
  recorder_.removeRobot(name);
}

void NodeRecording::afterStep(const Simulation& simulation) {
  recorder_.afterStep(simulation);
  for (auto& [name, commands] : commands_) {
    const auto& plugins = commands.robot->plugins();
    for (size_t i = 0; i < plugins.size(); ++i) {
      if (plugins[i]->portGroupsRevision() == commands.revisions[i]) continue;
      subscribeCommands(commands);  // a controller came or went
      break;
    }
  }
}

void NodeRecording::subscribeCommands(Commands& commands) {
  commands.revisions.clear();
  for (const auto& plugin : commands.robot->plugins())
    commands.revisions.push_back(plugin->portGroupsRevision());
  std::map<std::string, ros::Subscriber> subscribers;
  for (const CommandTopic& command : recorder_.commandTopics(commands.robot->name())) {
    auto kept = commands.subscribers.find(command.topic);
    if (kept != commands.subscribers.end()) {
      subscribers.insert(commands.subscribers.extract(kept));
      continue;
    }
    const boost::function<void(const topic_tools::ShapeShifter::ConstPtr&)> record =
        [this, topic = command.topic](const topic_tools::ShapeShifter::ConstPtr& message) {
          recorder_.command(topic, message, sim_time_());
        };
    subscribers[command.topic] =
        ros::NodeHandle().subscribe<topic_tools::ShapeShifter>(command.topic, 100, record);
  }
  commands.subscribers = std::move(subscribers);
}

}  // namespace bullet_sim
