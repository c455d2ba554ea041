#include "robot_recording.h"

#include <ros/names.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <type_traits>

namespace bullet_sim {

namespace {

/// The types a bag leaves out unless ~record_topics names them: they are most of its bytes.
const std::set<std::string> kBulkyTypes = {"sensor_msgs/Image", "sensor_msgs/PointCloud2",
                                           "sensor_msgs/PointCloud"};

template <class Message>
std::string typeOf() {
  return ros::message_traits::datatype<Message>();
}

/// The ROS type of an input's messages.
std::string commandType(const InputSink& sink) {
  return std::visit(
      [](const auto& handler) -> std::string {
        using Handler = std::decay_t<decltype(handler)>;
        if constexpr (std::is_same_v<Handler, InputHandler<Twist>>) return "geometry_msgs/Twist";
        if constexpr (std::is_same_v<Handler, InputHandler<JointTrajectory>>)
          return "trajectory_msgs/JointTrajectory";
        if constexpr (std::is_same_v<Handler, InputHandler<Float64Command>>) return "std_msgs/Float64";
        if constexpr (std::is_same_v<Handler, InputHandler<Float64ArrayCommand>>)
          return "std_msgs/Float64MultiArray";
        if constexpr (std::is_same_v<Handler, InputHandler<BoolCommand>>) return "std_msgs/Bool";
      },
      sink);
}

/// Where a joint puts its child link in its parent's frame at position `q` [rad] or [m] (KDL's segment pose).
Eigen::Isometry3d jointTransform(const JointSpec& joint, double q) {
  switch (joint.type) {
    case JointSpec::Type::kRevolute:
    case JointSpec::Type::kContinuous: return joint.origin * Eigen::AngleAxisd(q, joint.axis);
    case JointSpec::Type::kPrismatic: return joint.origin * Eigen::Translation3d(q * joint.axis);
    case JointSpec::Type::kFixed: break;
  }
  return joint.origin;
}

geometry_msgs::TransformStamped linkTransform(const Eigen::Isometry3d& pose, double stamp,
                                              const std::string& parent, const std::string& child) {
  geometry_msgs::TransformStamped transform = tf2::eigenToTransform(pose);
  transform.header = header(stamp, parent);
  transform.child_frame_id = child;
  return transform;
}

bool isJointStatesTopic(const std::string& topic) {
  const std::string bare = withoutSlashes(topic);
  return bare == "joint_states" ||
         (bare.size() > 13 && bare.compare(bare.size() - 13, 13, "/joint_states") == 0);
}

}  // namespace

TopicFilter::TopicFilter(const std::vector<std::string>& patterns) {
  for (const auto& pattern : patterns) {
    try {
      patterns_.emplace_back(pattern, std::regex::ECMAScript | std::regex::optimize);
    } catch (const std::regex_error& e) {
      throw std::invalid_argument("topic pattern [" + pattern + "] is no regular expression: " + e.what());
    }
  }
}

bool TopicFilter::records(const std::string& topic, const std::string& type) const {
  if (patterns_.empty()) return !kBulkyTypes.count(type);
  return std::any_of(patterns_.begin(), patterns_.end(),
                     [&](const std::regex& pattern) { return std::regex_match(topic, pattern); });
}

RobotRecording::RobotRecording(const Robot& robot, RobotNames names, const TopicFilter& filter,
                               double ground_truth_rate)
    : robot_(robot), name_(robot.name()), names_(std::move(names)), filter_(filter),
      ground_truth_timer_(ground_truth_rate) {
  namespace_ = withoutSlashes(names_.robot_namespace);
  if (namespace_.empty() && !robot.plugins().empty())
    namespace_ = withoutSlashes(robot.plugins()[0]->robotNamespace());
  for (const JointSpec& joint : robot.body().spec().joints) {
    if (joint.moves()) moving_joints_[joint.name] = &joint;
  }
  for (const auto& plugin : robot.plugins()) {
    connect(*plugin, plugin->ports(), outputs_);
    watched_.push_back({plugin.get(), ~plugin->portGroupsRevision()});  // connected by the first refresh
  }
  refreshGroups();
}

std::string RobotRecording::topicOf(const Plugin& plugin, const std::string& topic) const {
  const std::string ns = names_.robot_namespace.empty() ? plugin.robotNamespace() : names_.robot_namespace;
  try {
    return ros::names::resolve("/" + withoutSlashes(ns), topic);
  } catch (const ros::InvalidNameException&) {
    return "";  // the node refuses it too, and says so
  }
}

std::string RobotRecording::commandTopic(const Plugin& plugin, const std::string& topic,
                                         const std::string& type) const {
  const std::string name = topicOf(plugin, topic);
  return !name.empty() && filter_.records(name, type) ? name : "";
}

void RobotRecording::connect(const Plugin& plugin, const PluginPorts& ports,
                             std::vector<Output>& into) const {
  for (const OutputPort& port : ports.outputs) {
    std::visit([&](const auto* stream) { connectStream(plugin, port.topic, stream, port.demand, into); },
               port.stream);
  }
}

namespace {

/// When a sample is recorded in the bag: a ray sensor's at its stamp (cast behind physics, it is published
/// some steps later, SimulationOptions::lockstep), every other one at the step it was published in, its
/// stamp.
template <class Sample>
double recordedAt(const Sample& sample, double sim_time) {
  if constexpr (std::is_same_v<Sample, LaserScan> || std::is_base_of_v<PointCloud, Sample> ||
                std::is_same_v<Sample, RangeSample>) {
    return sample.stamp;
  }
  return sim_time;
}

}  // namespace

template <class Sample>
void RobotRecording::connectStream(const Plugin& plugin, const std::string& topic,
                                   const Stream<Sample>* stream, Demand* demand,
                                   std::vector<Output>& into) const {
  const FramePrefix frames = names_.plugin_frames(plugin);
  using Message = decltype(toMessage(stream->latest(), frames));
  const std::string name = std::is_same_v<Sample, TransformSample> ? "/tf" : topicOf(plugin, topic);
  const bool recorded = !name.empty() && filter_.records(name, typeOf<Message>());
  // robot_state_publisher turns each joint_states message into the moving links' transforms.
  bool links = false;
  if constexpr (std::is_same_v<Sample, JointStateSample>) {
    links = isJointStatesTopic(topic) && filter_.records("/tf", typeOf<tf2_msgs::TFMessage>());
  }
  if (!recorded && !links) return;
  into.push_back({[stream] { return stream->count(); },
                  [this, stream, frames, name, recorded, links](BagWriter& writer, double sim_time) {
                    if (recorded)
                      writer.write(name, recordedAt(stream->latest(), sim_time),
                                   toMessage(stream->latest(), frames));
                    if constexpr (std::is_same_v<Sample, JointStateSample>) {
                      if (links) writer.write("/tf", sim_time, movingTransforms(stream->latest()));
                    }
                  },
                  0, recorded ? demand : nullptr});
}

void RobotRecording::refreshGroups() {
  for (auto& watched : watched_) {
    const uint64_t revision = watched.plugin->portGroupsRevision();
    if (revision == watched.revision) continue;
    watched.revision = revision;
    const std::vector<PortGroup> groups = watched.plugin->portGroups();
    for (auto it = groups_.begin(); it != groups_.end();) {
      const auto& [owner, id] = it->first;
      const bool gone =
          owner == watched.plugin &&
          std::none_of(groups.begin(), groups.end(), [id = id](const PortGroup& g) { return g.id == id; });
      it = gone ? groups_.erase(it) : std::next(it);
    }
    for (const PortGroup& group : groups) {
      const auto key = std::make_pair(watched.plugin, group.id);
      if (!groups_.count(key)) connect(*watched.plugin, *group.ports, groups_[key]);
    }
  }
}

void RobotRecording::afterStep(const Simulation& simulation, BagWriter& writer) {
  refreshGroups();
  const double now = simulation.time();
  writeOutputs(outputs_, writer, now);
  for (auto& [group, outputs] : groups_) writeOutputs(outputs, writer, now);
  if (ground_truth_timer_.due({now, simulation.stepSize()})) writeGroundTruth(writer, now);
}

void RobotRecording::writeOutputs(std::vector<Output>& outputs, BagWriter& writer, double sim_time) {
  for (Output& output : outputs) {
    const uint64_t count = output.count();
    if (count != output.seen) {
      output.seen = count;
      output.write(writer, sim_time);
    }
    if (output.demand) output.demand->wanted = true;
  }
}

tf2_msgs::TFMessage RobotRecording::movingTransforms(const JointStateSample& states) const {
  tf2_msgs::TFMessage message;
  for (size_t i = 0; i < states.names.size() && i < states.positions.size(); ++i) {
    const auto joint = moving_joints_.find(states.names[i]);
    if (joint == moving_joints_.end()) continue;
    const JointSpec& spec = *joint->second;
    message.transforms.push_back(linkTransform(jointTransform(spec, states.positions[i]), states.stamp,
                                               names_.link_frames(spec.parent),
                                               names_.link_frames(spec.child)));
  }
  return message;
}

std::vector<geometry_msgs::TransformStamped> RobotRecording::fixedTransforms(double stamp) const {
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (const JointSpec& joint : robot_.body().spec().joints) {
    if (joint.moves()) continue;
    transforms.push_back(linkTransform(joint.origin, stamp, names_.link_frames(joint.parent),
                                       names_.link_frames(joint.child)));
  }
  return transforms;
}

void RobotRecording::writeGroundTruth(BagWriter& writer, double sim_time) const {
  const std::string topic = "/" + (namespace_.empty() ? "" : namespace_ + "/") + "ground_truth";
  if (!filter_.records(topic, typeOf<nav_msgs::Odometry>())) return;
  const RobotBody& body = robot_.body();
  const std::string& root = body.spec().root;
  Odometry truth;
  truth.stamp = sim_time;
  truth.frame_id = "world";
  truth.child_frame_id = names_.link_frames(root);
  truth.pose = body.linkPose(root);
  const Eigen::Matrix3d to_body = truth.pose.linear().transpose();
  truth.linear_velocity = to_body * body.linkLinearVelocity(root);
  truth.angular_velocity = to_body * body.linkAngularVelocity(root);
  writer.write(topic, sim_time, toMessage(truth, FramePrefix()));
}

std::vector<CommandTopic> RobotRecording::commandTopics() const {
  std::vector<CommandTopic> topics;
  const auto add = [&](const Plugin& plugin, const PluginPorts& ports) {
    for (const InputPort& port : ports.inputs) {
      const std::string type = commandType(port.sink);
      const std::string name = commandTopic(plugin, port.topic, type);
      if (!name.empty()) topics.push_back({name, type});
    }
  };
  for (const auto& plugin : robot_.plugins()) {
    add(*plugin, plugin->ports());
    for (const PortGroup& group : plugin->portGroups()) add(*plugin, *group.ports);
  }
  return topics;
}

}  // namespace bullet_sim
