#include "bag_recorder.h"

#include <cmath>
#include <filesystem>

namespace bullet_sim {

namespace {

/// `settings` checked, its path ending in .bag; std::invalid_argument naming what is wrong.
BagSettings validated(BagSettings settings) {
  if (settings.path.empty()) throw std::invalid_argument("the bag's path is empty");
  const std::string extension = ".bag";
  if (settings.path.size() < extension.size() ||
      settings.path.compare(settings.path.size() - extension.size(), extension.size(), extension) != 0)
    settings.path += extension;
  if (settings.compression != "none" && settings.compression != "lz4" && settings.compression != "bz2")
    throw std::invalid_argument("compression [" + settings.compression + "]: use none, lz4 or bz2");
  if (settings.chunk_size == 0) throw std::invalid_argument("chunk size 0: give a positive number of bytes");
  if (!(settings.ground_truth_rate >= 0) || !std::isfinite(settings.ground_truth_rate))
    throw std::invalid_argument("ground truth rate [" + std::to_string(settings.ground_truth_rate) +
                                "]: give a rate >= 0 Hz (0: every step)");
  return settings;
}

rosbag::CompressionType compressionOf(const std::string& name) {
  if (name == "lz4") return rosbag::compression::LZ4;
  if (name == "bz2") return rosbag::compression::BZ2;
  return rosbag::compression::Uncompressed;
}

/// FILE.bag for the first part, FILE_<part>.bag after.
std::string partPath(const std::string& path, size_t part) {
  if (part == 0) return path;
  return path.substr(0, path.size() - 4) + "_" + std::to_string(part) + ".bag";
}

/// The connection header of a latched topic, as `rosbag record` writes one (without caller id).
template <class Message>
ConnectionHeader latchedHeader(const std::string& topic) {
  auto header = boost::make_shared<ros::M_string>();
  (*header)["topic"] = topic;
  (*header)["type"] = ros::message_traits::datatype<Message>();
  (*header)["md5sum"] = ros::message_traits::md5sum<Message>();
  (*header)["message_definition"] = ros::message_traits::definition<Message>();
  (*header)["latching"] = "1";
  return header;
}

}  // namespace

BagRecorder::BagRecorder(BagSettings settings, RecorderErrors errors)
    : settings_(validated(std::move(settings))), filter_(settings_.topics), errors_(std::move(errors)),
      latched_tf_static_(latchedHeader<tf2_msgs::TFMessage>("/tf_static")) {
  options_.compression = compressionOf(settings_.compression);
  options_.chunk_size = settings_.chunk_size;
  std::error_code ignored;  // a folder that cannot be made is reported by the opening
  std::filesystem::create_directories(std::filesystem::path(settings_.path).parent_path(), ignored);
  open();
}

BagRecorder::~BagRecorder() { close(); }

void BagRecorder::open() {
  paths_.push_back(partPath(settings_.path, paths_.size()));
  writer_ = std::make_unique<BagWriter>(paths_.back(), options_, errors_);
  fixed_transforms_due_ = !robots_.empty();
}

void BagRecorder::addRobot(const Robot& robot, const std::string& robot_namespace,
                           const std::string& tf_prefix) {
  RobotNames names;
  names.robot_namespace = robot_namespace;
  names.plugin_frames = [tf_prefix](const Plugin& plugin) {
    return FramePrefix(plugin.tfPrefixRule() == TfPrefixRule::kNone ? "" : tf_prefix, plugin.globalFrames());
  };
  names.link_frames = FramePrefix(tf_prefix);
  addRobot(robot, std::move(names));
}

void BagRecorder::addRobot(const Robot& robot, RobotNames names) {
  robots_.push_back(
      std::make_unique<RobotRecording>(robot, std::move(names), filter_, settings_.ground_truth_rate));
  fixed_transforms_due_ = true;
}

void BagRecorder::removeRobot(const std::string& name) {
  const auto gone =
      std::remove_if(robots_.begin(), robots_.end(), [&](const auto& r) { return r->name() == name; });
  if (gone == robots_.end()) return;
  robots_.erase(gone, robots_.end());
  fixed_transforms_due_ = !robots_.empty();
}

void BagRecorder::afterStep(const Simulation& simulation) {
  if (!writer_ || !writer_->recording()) return;
  if (fixed_transforms_due_) writeFixedTransforms(simulation.time());
  for (const auto& robot : robots_) robot->afterStep(simulation, *writer_);
}

/// One message holding every robot's fixed links, as tf2's static broadcaster keeps them: a latched topic
/// replays only its last message.
void BagRecorder::writeFixedTransforms(double sim_time) {
  fixed_transforms_due_ = false;
  if (!filter_.records("/tf_static", ros::message_traits::datatype<tf2_msgs::TFMessage>())) return;
  tf2_msgs::TFMessage message;
  for (const auto& robot : robots_) {
    for (auto& transform : robot->fixedTransforms(sim_time))
      message.transforms.push_back(std::move(transform));
  }
  writer_->write("/tf_static", sim_time, std::move(message), latched_tf_static_);
}

void BagRecorder::command(const Robot& robot, const RobotInput<Twist>& input, const Twist& twist,
                          double sim_time) {
  if (!writer_ || !writer_->recording()) return;
  for (const auto& recording : robots_) {
    if (recording->name() != robot.name()) continue;
    const std::string topic = recording->commandTopic(*input.plugin, input.topic, "geometry_msgs/Twist");
    if (!topic.empty()) writer_->write(topic, sim_time, toMessage(twist));
  }
}

void BagRecorder::command(const std::string& topic, const topic_tools::ShapeShifter::ConstPtr& message,
                          double sim_time) {
  if (writer_ && writer_->recording()) writer_->write(topic, sim_time, message);
}

std::vector<CommandTopic> BagRecorder::commandTopics(const std::string& robot) const {
  for (const auto& recording : robots_) {
    if (recording->name() == robot) return recording->commandTopics();
  }
  return {};
}

void BagRecorder::restart() {
  if (!writer_ || !writer_->recording()) return;  // recording stopped on an error: it stays stopped
  if (!writer_->close()) return;
  closed_.push_back(writer_->path());
  for (const auto& robot : robots_) robot->restart();
  open();
}

std::vector<std::string> BagRecorder::close() {
  if (writer_ && writer_->close()) closed_.push_back(writer_->path());
  writer_.reset();
  return closed_;
}

}  // namespace bullet_sim

// The library's entry point for tools that load it when a run asks for a bag (tools/run_recorder.h).
extern "C" bullet_sim::RunRecorder* bullet_sim_new_bag_recorder(const bullet_sim::BagSettings* settings,
                                                                const bullet_sim::RecorderErrors* errors,
                                                                std::string* error) {
  try {
    return std::make_unique<bullet_sim::BagRecorder>(*settings, *errors).release();
  } catch (const std::invalid_argument& e) {
    *error = e.what();
    return nullptr;
  }
}
