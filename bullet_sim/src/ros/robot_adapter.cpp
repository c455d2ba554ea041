#include "robot_adapter.h"

#include <camera_info_manager/camera_info_manager.h>
#include <image_transport/image_transport.h>
#include <ros/publication.h>
#include <ros/topic_manager.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Float64MultiArray.h>
#include <std_srvs/Empty.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <algorithm>
#include <optional>

#include "action_server.h"
#include "controller_manager_services.h"
#include "listened_publisher.h"
#include "messages.h"
#include "trajectory_messages.h"

namespace bullet_sim {

namespace {

constexpr double kIgnoredInputWarningPeriod = 5;  // [s] of ROS time: one warning per topic per period

// One conversion per input type; nullopt when the message holds nothing to take.

std::optional<Twist> fromMessage(const geometry_msgs::Twist& message) {
  Twist twist;
  tf2::fromMsg(message.linear, twist.linear);
  tf2::fromMsg(message.angular, twist.angular);
  return twist;
}

std::optional<JointTrajectory> fromMessage(const trajectory_msgs::JointTrajectory& message) {
  return toTrajectory(message);
}

std::optional<Float64Command> fromMessage(const std_msgs::Float64& message) {
  return Float64Command{message.data};
}

std::optional<Float64ArrayCommand> fromMessage(const std_msgs::Float64MultiArray& message) {
  return Float64ArrayCommand{message.data};
}

std::optional<BoolCommand> fromMessage(const std_msgs::Bool& message) {
  return BoolCommand{static_cast<bool>(message.data)};
}

/// Why roscpp gave an empty publisher or subscriber (it only logs): most often another type on the topic in
/// this process, as rosgraph_msgs/Clock on /clock.
std::string refusal(const std::string& where, const std::string& what, const std::string& type,
                    const std::string& topic) {
  const ros::PublicationPtr there = ros::TopicManager::instance()->lookupPublication(topic);
  const std::string carrying = there ? ": it carries " + there->getDataType() : "";
  return where + " cannot " + what + " " + type + " on [" + topic + "]" + carrying + "; it runs without it";
}

}  // namespace

struct RobotAdapter::Connection {
  mutable ros::NodeHandle handle;  // advertise and subscribe are not const
  FramePrefix frames;
  Connections& into;
  std::string where;  ///< the plugin, for what it cannot connect
};

RobotAdapter::RobotAdapter(Robot& robot, const std::string& robot_namespace,
                           const ListenedPublisher& tf, FrameOwners& owners,
                           std::function<double()> sim_time)
    : robot_name_(robot.name()),
      namespace_(withoutSlashes(robot_namespace)),
      tf_(tf),
      owners_(owners),
      sim_time_(std::move(sim_time)) {
  for (const auto& plugin : robot.plugins()) {
    connect(*plugin, plugin->ports(), fixed_);
    watched_.push_back({plugin.get(), plugin->portGroupsRevision()});
    reconnectGroups(*plugin);
  }
}

void RobotAdapter::connect(const Plugin& plugin, const PluginPorts& ports, Connections& into) {
  const Connection connection{handleFor(plugin.robotNamespace()), framesOf(plugin), into, plugin.where()};
  try {
    for (const auto& port : ports.inputs) subscribe(connection, port);
    for (const auto& port : ports.outputs) advertise(connection, port);
    for (const auto& port : ports.services) serve(connection, port);
    for (const auto& port : ports.actions) serveAction(connection, port);
  } catch (const ros::Exception& e) {  // a name ROS refuses, e.g. from a controller's parameters
    cannotConnect(plugin.where() + ": " + e.what());
  }
}

void RobotAdapter::cannotConnect(const std::string& why) {
  ROS_WARN("[%s] %s", robot_name_.c_str(), why.c_str());
  problems_.push_back(why);
}

void RobotAdapter::checkTypeElsewhere(const Connection& plugin, const std::string& what,
                                      const std::string& type, const std::string& topic) {
  if (!published_types_) {
    published_types_.emplace();
    ros::master::V_TopicInfo topics;
    if (ros::master::getTopics(topics)) {
      for (const auto& info : topics) (*published_types_)[info.name] = info.datatype;
    }
  }
  const auto found = published_types_->find(topic);
  if (found == published_types_->end() || found->second == type || found->second == "*") return;
  cannotConnect(plugin.where + " cannot " + what + " " + type + " on [" + topic +
                "]: another node publishes " + found->second +
                " there, and ROS joins only the same types: nothing passes between them");
}

void RobotAdapter::refreshPorts() {
  for (auto& watched : watched_) {
    const uint64_t revision = watched.plugin->portGroupsRevision();
    if (revision == watched.revision) continue;
    watched.revision = revision;
    reconnectGroups(*watched.plugin);
  }
}

void RobotAdapter::reconnectGroups(const Plugin& plugin) {
  const std::vector<PortGroup> groups = plugin.portGroups();
  for (auto it = groups_.begin(); it != groups_.end();) {
    const auto& [owner, id] = it->first;
    const bool gone =
        owner == &plugin && std::none_of(groups.begin(), groups.end(),
                                         [id = id](const PortGroup& group) { return group.id == id; });
    it = gone ? groups_.erase(it) : std::next(it);
  }
  for (const auto& group : groups) {
    if (groups_.count({&plugin, group.id})) continue;
    const size_t logged = topics_.size();
    connect(plugin, *group.ports, groups_[{&plugin, group.id}]);
    for (size_t t = logged; t < topics_.size(); ++t)
      ROS_INFO("[%s] %s: %s", robot_name_.c_str(), group.name.c_str(), topics_[t].c_str());
  }
}

void RobotAdapter::serve(const Connection& plugin, const ServicePort& port) {
  auto& services = plugin.into.services;
  if (const auto* handler = std::get_if<ServiceHandler<EmptyRequest>>(&port.handler)) {
    services.push_back(plugin.handle.advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>(
        port.name,
        [handler = *handler, name = robot_name_](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
          EmptyRequest::Reply reply;
          const std::string refused = handler(EmptyRequest{}, reply);
          if (!refused.empty()) ROS_WARN("[%s] %s", name.c_str(), refused.c_str());
          return refused.empty();
        }));
  } else if (const auto* query = std::get_if<ServiceHandler<QueryTrajectoryStateRequest>>(&port.handler)) {
    services.push_back(serveQueryState(plugin.handle, port.name, *query, robot_name_));
  } else {
    services.push_back(serveControllerManager(plugin.handle, port.name, port.handler, robot_name_));
  }
  topics_.push_back(services.back().getService() + " (service)");
}

void RobotAdapter::serveAction(const Connection& plugin, const ActionPort& port) {
  std::visit(
      [&](const auto& handlers) {
        using Handlers = std::decay_t<decltype(handlers)>;
        static_assert(std::is_same_v<Handlers, ActionHandlers<FollowJointTrajectoryAction>>,
                      "an action type without its messages");
        plugin.into.actions.push_back(std::make_shared<ActionBridge<FollowJointTrajectoryMessages>>(
            plugin.handle, port.name, handlers, sim_time_, robot_name_));
      },
      port.sink);
  topics_.push_back(plugin.into.actions.back()->name() + " (action)");
}

template <class Message, class Sample, class Convert>
void RobotAdapter::advertiseStream(const Connection& plugin, const OutputPort& port,
                                   const Stream<Sample>* stream, Convert convert) {
  const auto publisher = ListenedPublisher::advertise<Message>(plugin.handle, port.topic, 10);
  if (!publisher) {
    const std::string type = ros::message_traits::DataType<Message>::value();
    return cannotConnect(refusal(plugin.where, "publish", type, plugin.handle.resolveName(port.topic)));
  }
  const std::string topic = publisher.publisher().getTopic();
  checkTypeElsewhere(plugin, "publish", ros::message_traits::DataType<Message>::value(), topic);
  plugin.into.publishers.push_back(publisher.publisher());
  topics_.push_back(topic);
  plugin.into.outputs.push_back({[stream] { return stream->count(); },
                      [publisher, stream, convert, frames = plugin.frames] {
                        publisher.publishBuilt([&] { return convert(stream->latest(), frames); });
                      },
                      0, port.demand, [publisher] { return publisher.listeners(); }});
}

void RobotAdapter::advertiseImages(const Connection& plugin, const OutputPort& port,
                                   const Stream<CameraImage>* stream) {
  image_transport::ImageTransport transport(plugin.handle);
  image_transport::Publisher publisher = transport.advertise(port.topic, 2);
  checkTypeElsewhere(plugin, "publish", "sensor_msgs/Image", publisher.getTopic());
  plugin.into.image_publishers.push_back(publisher);
  topics_.push_back(publisher.getTopic());
  plugin.into.outputs.push_back({[stream] { return stream->count(); },
                      [publisher, stream, frames = plugin.frames] {
                        publisher.publish(toMessage(stream->latest(), frames));
                      },
                      0, port.demand, [publisher] { return publisher.getNumSubscribers(); }});
}

void RobotAdapter::advertiseCameraInfo(const Connection& plugin, const OutputPort& port,
                                       const Stream<CameraInfo>* stream) {
  // One camera_info_manager per camera, as gazebo_ros_camera_utils has: its set_camera_info service changes
  // what every camera_info topic of the camera publishes.
  const CameraInfo& initial = stream->latest();
  const ros::NodeHandle camera_handle(plugin.handle, initial.camera_name);
  auto& manager = info_managers_[camera_handle.getNamespace()];
  if (!manager) {
    manager = std::make_shared<camera_info_manager::CameraInfoManager>(camera_handle, initial.camera_name);
    sensor_msgs::CameraInfo info;
    info.width = initial.width;
    info.height = initial.height;
    info.distortion_model = initial.distortion_model;
    info.D.assign(initial.D.begin(), initial.D.end());
    std::copy(initial.K.begin(), initial.K.end(), info.K.begin());
    std::copy(initial.R.begin(), initial.R.end(), info.R.begin());
    std::copy(initial.P.begin(), initial.P.end(), info.P.begin());
    manager->setCameraInfo(info);
  }
  ros::Publisher publisher = plugin.handle.advertise<sensor_msgs::CameraInfo>(port.topic, 2);
  if (!publisher) {
    const std::string topic = plugin.handle.resolveName(port.topic);
    return cannotConnect(refusal(plugin.where, "publish", "sensor_msgs/CameraInfo", topic));
  }
  checkTypeElsewhere(plugin, "publish", "sensor_msgs/CameraInfo", publisher.getTopic());
  plugin.into.publishers.push_back(publisher);
  topics_.push_back(publisher.getTopic());
  plugin.into.outputs.push_back({[stream] { return stream->count(); },
                      [publisher, stream, manager, frames = plugin.frames] {
                        sensor_msgs::CameraInfo info = manager->getCameraInfo();
                        info.header = header(stream->latest().stamp, frames(stream->latest().frame_id));
                        publisher.publish(info);
                      },
                      0, port.demand, [publisher] { return publisher.getNumSubscribers(); }});
}

void RobotAdapter::broadcast(const Connection& plugin, const Stream<TransformSample>* stream) {
  plugin.into.outputs.push_back({[stream] { return stream->count(); },
                      [this, stream, frames = plugin.frames] {
                        const TransformSample& sample = stream->latest();
                        for (const auto& frame : sample.frames) claimFrame(frames(frame.child));
                        tf_.publishBuilt([&] {  // one message per sample
                          tf2_msgs::TFMessage message;
                          for (const auto& frame : sample.frames) {
                            message.transforms.push_back(tf2::eigenToTransform(frame.pose));
                            message.transforms.back().header = header(sample.stamp, frames(frame.parent));
                            message.transforms.back().child_frame_id = frames(frame.child);
                          }
                          return message;
                        });
                      }});
}

void RobotAdapter::advertise(const Connection& plugin, const OutputPort& port) {
  const auto convert = [](const auto& sample, const FramePrefix& frames) {
    return toMessage(sample, frames);
  };
  std::visit(
      [&](const auto* stream) {
        using Sample = std::decay_t<decltype(stream->latest())>;
        if constexpr (std::is_same_v<Sample, TransformSample>) {
          broadcast(plugin, stream);
        } else if constexpr (std::is_same_v<Sample, CameraImage>) {
          advertiseImages(plugin, port, stream);
        } else if constexpr (std::is_same_v<Sample, CameraInfo>) {
          advertiseCameraInfo(plugin, port, stream);
        } else {
          using Message = decltype(toMessage(stream->latest(), plugin.frames));
          advertiseStream<Message>(plugin, port, stream, convert);
        }
      },
      port.stream);
}

template <class Message, class Input>
void RobotAdapter::subscribeAs(const Connection& plugin, const InputPort& port,
                               const InputHandler<Input>& handler) {
  const std::string topic = plugin.handle.resolveName(port.topic);
  // Throttled per topic (not per line of code): a bad stream on one topic must not hide the warning of
  // another.
  const auto warn = [name = robot_name_, topic,
                     last = std::make_shared<double>(-kIgnoredInputWarningPeriod)](const std::string& why) {
    if (why.empty()) return;
    const double now = ros::Time::now().toSec();
    if (now >= *last && now < *last + kIgnoredInputWarningPeriod) return;
    *last = now;
    ROS_WARN("[%s] %s: ignored %s", name.c_str(), topic.c_str(), why.c_str());
  };
  // A plugin that cares how many publish to the input is told with each message, as ros_controllers' diff
  // drive asks in its callback: asking roscpp scans every subscription by name.
  ros::Subscriber subscriber = plugin.handle.subscribe<Message>(
      port.topic, 10,
      [this, handler, warn, topic, publishers = port.publishers](const typename Message::ConstPtr& message) {
        if (publishers) publishers->count = ros::TopicManager::instance()->getNumPublishers(topic);
        if (const std::optional<Input> input = fromMessage(*message)) warn(handler(*input, sim_time_()));
      });
  if (!subscriber) {
    const std::string type = ros::message_traits::DataType<Message>::value();
    return cannotConnect(refusal(plugin.where, "subscribe", type, topic));
  }
  checkTypeElsewhere(plugin, "subscribe to", ros::message_traits::DataType<Message>::value(),
                     subscriber.getTopic());
  plugin.into.subscribers.push_back(subscriber);
  topics_.push_back(subscriber.getTopic() + " (in)");
}

void RobotAdapter::subscribe(const Connection& plugin, const InputPort& port) {
  std::visit(
      [&](const auto& handler) {
        using Handler = std::decay_t<decltype(handler)>;
        if constexpr (std::is_same_v<Handler, InputHandler<Twist>>) {
          subscribeAs<geometry_msgs::Twist>(plugin, port, handler);
        } else if constexpr (std::is_same_v<Handler, InputHandler<JointTrajectory>>) {
          subscribeAs<trajectory_msgs::JointTrajectory>(plugin, port, handler);
        } else if constexpr (std::is_same_v<Handler, InputHandler<Float64Command>>) {
          subscribeAs<std_msgs::Float64>(plugin, port, handler);
        } else if constexpr (std::is_same_v<Handler, InputHandler<Float64ArrayCommand>>) {
          subscribeAs<std_msgs::Float64MultiArray>(plugin, port, handler);
        } else {
          static_assert(std::is_same_v<Handler, InputHandler<BoolCommand>>, "an input type without a topic");
          subscribeAs<std_msgs::Bool>(plugin, port, handler);
        }
      },
      port.sink);
}

ros::NodeHandle RobotAdapter::handleFor(const std::string& plugin_namespace) const {
  const std::string ns = namespace_.empty() ? withoutSlashes(plugin_namespace) : namespace_;
  return ns.empty() ? ros::NodeHandle() : ros::NodeHandle("/" + ns);
}

FramePrefix RobotAdapter::framesOf(const Plugin& plugin) const {
  return framePrefixOf(handleFor(plugin.robotNamespace()), plugin);
}

void RobotAdapter::claimFrame(const std::string& child) {
  const auto [owner, first] = owners_.robot_of.emplace(child, robot_name_);
  if (!first && owner->second != robot_name_ && owners_.warned.insert(child + " " + robot_name_).second) {
    ROS_WARN(
        "robots [%s] and [%s] both publish frame [%s] on /tf: set the tf_prefix parameter in each robot's "
        "namespace (e.g. <param name=\"tf_prefix\" value=\"%s\"/> in its <group ns>), which its plugins "
        "and robot_state_publisher read",
        owner->second.c_str(), robot_name_.c_str(), child.c_str(), robot_name_.c_str());
  }
}

RobotAdapter::~RobotAdapter() {
  for (auto it = owners_.robot_of.begin(); it != owners_.robot_of.end();) {
    it = it->second == robot_name_ ? owners_.robot_of.erase(it) : std::next(it);
  }
}

void RobotAdapter::publish() {
  refreshPorts();  // first: the outputs of an unloaded controller are gone
  publish(fixed_);
  for (auto& [group, connections] : groups_) publish(connections);
}

void RobotAdapter::publish(Connections& connections) {
  for (auto& output : connections.outputs) {
    const uint64_t count = output.count();
    if (count != output.seen) {
      output.seen = count;
      output.publish();
    }
    if (output.demand) output.demand->wanted = output.subscribers() > 0;
  }
  for (auto& action : connections.actions) action->sendReports();
}

}  // namespace bullet_sim
