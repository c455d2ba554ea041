#include "robot_adapter.h"

#include <camera_info_manager/camera_info_manager.h>
#include <control_msgs/JointControllerState.h>
#include <gazebo_msgs/ContactsState.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/Vector3Stamped.h>
#include <image_transport/image_transport.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/Range.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Float64MultiArray.h>
#include <std_srvs/Empty.h>
#include <tf2_eigen/tf2_eigen.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <algorithm>
#include <optional>

#include "action_server.h"
#include "controller_manager_services.h"
#include "trajectory_messages.h"

namespace bullet_sim {

namespace {

std::string withoutSlashes(std::string text) {
  while (!text.empty() && text.front() == '/') text.erase(text.begin());
  while (!text.empty() && text.back() == '/') text.pop_back();
  return text;
}

std_msgs::Header header(double stamp, const std::string& frame_id) {
  std_msgs::Header header;
  header.stamp = ros::Time(stamp);
  header.frame_id = frame_id;
  return header;
}

// One conversion per output type.

nav_msgs::Odometry toMessage(const Odometry& odometry, const FramePrefix& frames) {
  nav_msgs::Odometry message;
  message.header = header(odometry.stamp, frames(odometry.frame_id));
  message.child_frame_id = frames(odometry.child_frame_id);
  message.pose.pose = tf2::toMsg(odometry.pose);
  tf2::toMsg(odometry.linear_velocity, message.twist.twist.linear);
  tf2::toMsg(odometry.angular_velocity, message.twist.twist.angular);
  std::copy(odometry.pose_covariance.begin(), odometry.pose_covariance.end(),
            message.pose.covariance.begin());
  std::copy(odometry.twist_covariance.begin(), odometry.twist_covariance.end(),
            message.twist.covariance.begin());
  return message;
}

sensor_msgs::JointState toMessage(const JointStateSample& states, const FramePrefix&) {
  sensor_msgs::JointState message;
  message.header.stamp = ros::Time(states.stamp);
  message.name = states.names;
  message.position = states.positions;
  message.velocity = states.velocities;
  message.effort = states.efforts;
  return message;
}

sensor_msgs::LaserScan toMessage(const LaserScan& scan, const FramePrefix& frames) {
  sensor_msgs::LaserScan message;
  message.header = header(scan.stamp, frames(scan.frame_id));
  message.angle_min = scan.angle_min;
  message.angle_max = scan.angle_max;
  message.angle_increment = scan.angle_increment;
  message.time_increment = 0;
  message.scan_time = scan.scan_time;
  message.range_min = scan.range_min;
  message.range_max = scan.range_max;
  message.ranges = scan.ranges;
  return message;
}

/// The velodyne driver's layout: x y z intensity (float32) and ring (uint16).
sensor_msgs::PointCloud2 toMessage(const PointCloud& cloud, const FramePrefix& frames) {
  sensor_msgs::PointCloud2 message;
  message.header = header(cloud.stamp, frames(cloud.frame_id));
  sensor_msgs::PointCloud2Modifier fields(message);
  fields.setPointCloud2Fields(5, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1,
                              sensor_msgs::PointField::FLOAT32, "z", 1, sensor_msgs::PointField::FLOAT32,
                              "intensity", 1, sensor_msgs::PointField::FLOAT32, "ring", 1,
                              sensor_msgs::PointField::UINT16);
  fields.resize(cloud.points.size());
  sensor_msgs::PointCloud2Iterator<float> x(message, "x"), intensity(message, "intensity");
  sensor_msgs::PointCloud2Iterator<uint16_t> ring(message, "ring");
  for (size_t i = 0; i < cloud.points.size(); ++i, ++x, ++intensity, ++ring) {
    x[0] = cloud.points[i].x();
    x[1] = cloud.points[i].y();
    x[2] = cloud.points[i].z();
    *intensity = cloud.intensities[i];
    *ring = cloud.rings[i];
  }
  message.is_dense = true;
  return message;
}

sensor_msgs::PointCloud toMessage(const LegacyPointCloud& cloud, const FramePrefix& frames) {
  sensor_msgs::PointCloud message;
  message.header = header(cloud.stamp, frames(cloud.frame_id));
  message.channels.resize(1);
  message.channels[0].name = "intensity";
  message.channels[0].values = cloud.intensities;
  message.points.resize(cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    message.points[i].x = cloud.points[i].x();
    message.points[i].y = cloud.points[i].y();
    message.points[i].z = cloud.points[i].z();
  }
  return message;
}

sensor_msgs::Imu toMessage(const ImuSample& sample, const FramePrefix& frames) {
  sensor_msgs::Imu message;
  message.header = header(sample.stamp, frames(sample.frame_id));
  message.orientation = tf2::toMsg(sample.orientation);
  tf2::toMsg(sample.angular_velocity, message.angular_velocity);
  tf2::toMsg(sample.linear_acceleration, message.linear_acceleration);
  for (int i = 0; i < 3; ++i) {
    message.orientation_covariance[4 * i] = sample.orientation_variance[i];
    message.angular_velocity_covariance[4 * i] = sample.angular_velocity_variance[i];
    message.linear_acceleration_covariance[4 * i] = sample.linear_acceleration_variance[i];
  }
  return message;
}

sensor_msgs::Image toMessage(const CameraImage& image, const FramePrefix& frames) {
  sensor_msgs::Image message;
  message.header = header(image.stamp, frames(image.frame_id));
  message.width = image.width;
  message.height = image.height;
  message.encoding = image.encoding;
  message.is_bigendian = false;
  message.step = image.step;
  message.data = image.data;
  return message;
}

/// gazebo_ros_openni_kinect's layout: x y z (float32) and rgb (packed in a float32), width x height.
sensor_msgs::PointCloud2 toMessage(const ColouredCloud& cloud, const FramePrefix& frames) {
  sensor_msgs::PointCloud2 message;
  message.header = header(cloud.stamp, frames(cloud.frame_id));
  sensor_msgs::PointCloud2Modifier fields(message);
  fields.setPointCloud2FieldsByString(2, "xyz", "rgb");
  fields.resize(cloud.points.size());
  message.width = cloud.width;
  message.height = cloud.height;
  message.row_step = message.point_step * message.width;
  sensor_msgs::PointCloud2Iterator<float> x(message, "x");
  sensor_msgs::PointCloud2Iterator<uint8_t> rgb(message, "rgb");
  for (size_t i = 0; i < cloud.points.size(); ++i, ++x, ++rgb) {
    x[0] = cloud.points[i].x();
    x[1] = cloud.points[i].y();
    x[2] = cloud.points[i].z();
    rgb[0] = cloud.rgb[i][2];  // PCL's packed rgb: blue in the lowest byte
    rgb[1] = cloud.rgb[i][1];
    rgb[2] = cloud.rgb[i][0];
  }
  message.is_dense = cloud.is_dense;
  return message;
}

sensor_msgs::Range toMessage(const RangeSample& sample, const FramePrefix& frames) {
  sensor_msgs::Range message;
  message.header = header(sample.stamp, frames(sample.frame_id));
  message.radiation_type = sample.infrared ? sensor_msgs::Range::INFRARED : sensor_msgs::Range::ULTRASOUND;
  message.field_of_view = sample.field_of_view;
  message.min_range = sample.min_range;
  message.max_range = sample.max_range;
  message.range = sample.range;
  return message;
}

sensor_msgs::NavSatFix toMessage(const NavSatFixSample& fix, const FramePrefix& frames) {
  sensor_msgs::NavSatFix message;
  message.header = header(fix.stamp, frames(fix.frame_id));
  message.status.status = fix.status;
  message.status.service = fix.service;
  message.latitude = fix.latitude;
  message.longitude = fix.longitude;
  message.altitude = fix.altitude;
  std::copy(fix.position_covariance.begin(), fix.position_covariance.end(),
            message.position_covariance.begin());
  message.position_covariance_type = fix.position_covariance_type;
  return message;
}

geometry_msgs::Vector3Stamped toMessage(const Vector3Sample& sample, const FramePrefix& frames) {
  geometry_msgs::Vector3Stamped message;
  message.header = header(sample.stamp, frames(sample.frame_id));
  tf2::toMsg(sample.vector, message.vector);
  return message;
}

geometry_msgs::Wrench toMessage(const ContactsSample::Wrench& wrench) {
  geometry_msgs::Wrench message;
  tf2::toMsg(wrench.force, message.force);
  tf2::toMsg(wrench.torque, message.torque);
  return message;
}

gazebo_msgs::ContactsState toMessage(const ContactsSample& contacts, const FramePrefix& frames) {
  gazebo_msgs::ContactsState message;
  message.header = header(contacts.stamp, frames(contacts.frame_id));
  for (const auto& state : contacts.states) {
    gazebo_msgs::ContactState& out = message.states.emplace_back();
    out.info = state.info;
    out.collision1_name = state.collision1;
    out.collision2_name = state.collision2;
    for (const auto& wrench : state.wrenches) out.wrenches.push_back(toMessage(wrench));
    out.total_wrench = toMessage(state.total_wrench);
    for (const auto& position : state.positions) tf2::toMsg(position, out.contact_positions.emplace_back());
    for (const auto& normal : state.normals) tf2::toMsg(normal, out.contact_normals.emplace_back());
    out.depths = state.depths;
  }
  return message;
}

control_msgs::JointControllerState toMessage(const JointControllerState& state, const FramePrefix&) {
  control_msgs::JointControllerState message;
  message.header.stamp = ros::Time(state.stamp);
  message.set_point = state.set_point;
  message.process_value = state.process_value;
  message.process_value_dot = state.process_value_dot;
  message.error = state.error;
  message.time_step = state.time_step;
  message.command = state.command;
  message.p = state.p;
  message.i = state.i;
  message.d = state.d;
  message.i_clamp = state.i_clamp;
  message.antiwindup = state.antiwindup;
  return message;
}

control_msgs::JointTrajectoryControllerState toMessage(const JointTrajectoryControllerState& state,
                                                      const FramePrefix&) {
  return toStateMessage(state);
}

geometry_msgs::TwistStamped toMessage(const StampedTwist& twist, const FramePrefix& frames) {
  geometry_msgs::TwistStamped message;
  message.header = header(twist.stamp, twist.frame_id.empty() ? "" : frames(twist.frame_id));
  tf2::toMsg(twist.twist.linear, message.twist.linear);
  tf2::toMsg(twist.twist.angular, message.twist.angular);
  return message;
}

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

std::optional<Float64Command> fromMessage(const std_msgs::Float64& message) { return Float64Command{message.data}; }

std::optional<Float64ArrayCommand> fromMessage(const std_msgs::Float64MultiArray& message) {
  return Float64ArrayCommand{message.data};
}

std::optional<BoolCommand> fromMessage(const std_msgs::Bool& message) {
  return BoolCommand{static_cast<bool>(message.data)};
}

}  // namespace

FramePrefix::FramePrefix(std::string prefix, std::set<std::string> global_frames)
    : prefix_(withoutSlashes(prefix)), global_frames_(std::move(global_frames)) {}

std::string FramePrefix::operator()(const std::string& frame) const {
  const std::string bare = withoutSlashes(frame);
  if (prefix_.empty() || global_frames_.count(bare)) return bare;
  return prefix_ + "/" + bare;
}

struct RobotAdapter::Connection {
  mutable ros::NodeHandle handle;  // advertise and subscribe are not const
  FramePrefix frames;
  Connections& into;
};

RobotAdapter::RobotAdapter(Robot& robot, const std::string& robot_namespace,
                           tf2_ros::TransformBroadcaster& tf, FrameOwners& owners,
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
  const Connection connection{handleFor(plugin.robotNamespace()), framesOf(plugin), into};
  try {
    for (const auto& port : ports.inputs) subscribe(connection, port);
    for (const auto& port : ports.outputs) advertise(connection, port);
    for (const auto& port : ports.services) serve(connection, port);
    for (const auto& port : ports.actions) serveAction(connection, port);
  } catch (const ros::Exception& e) {  // a name ROS refuses, e.g. from a controller's parameters
    ROS_ERROR("[%s] %s: %s", robot_name_.c_str(), plugin.where().c_str(), e.what());
  }
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
    const bool gone = owner == &plugin && std::none_of(groups.begin(), groups.end(),
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
        port.name, [handler = *handler, name = robot_name_](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
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
  ros::Publisher publisher = plugin.handle.advertise<Message>(port.topic, 10);
  plugin.into.publishers.push_back(publisher);
  topics_.push_back(publisher.getTopic());
  plugin.into.outputs.push_back({[stream] { return stream->count(); },
                      [publisher, stream, convert, frames = plugin.frames] {
                        publisher.publish(convert(stream->latest(), frames));
                      },
                      0, port.demand, [publisher] { return publisher.getNumSubscribers(); }});
}

void RobotAdapter::advertiseImages(const Connection& plugin, const OutputPort& port,
                                   const Stream<CameraImage>* stream) {
  image_transport::ImageTransport transport(plugin.handle);
  image_transport::Publisher publisher = transport.advertise(port.topic, 2);
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
                        for (const auto& frame : sample.frames) {
                          geometry_msgs::TransformStamped transform = tf2::eigenToTransform(frame.pose);
                          transform.header = header(sample.stamp, frames(frame.parent));
                          transform.child_frame_id = frames(frame.child);
                          sendTransform(transform);
                        }
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
void RobotAdapter::subscribeAs(const Connection& plugin, const InputPort& port, const InputHandler<Input>& handler) {
  const auto warn = [name = robot_name_](const std::string& why) {
    if (!why.empty()) ROS_WARN_THROTTLE(5, "[%s] ignored %s", name.c_str(), why.c_str());
  };
  ros::Subscriber subscriber = plugin.handle.subscribe<Message>(
      port.topic, 10, [this, handler, warn](const typename Message::ConstPtr& message) {
        if (const std::optional<Input> input = fromMessage(*message)) warn(handler(*input, sim_time_()));
      });
  plugin.into.subscribers.push_back(subscriber);
  if (port.publishers) plugin.into.counted_inputs.emplace_back(subscriber, port.publishers);
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
  const ros::NodeHandle handle = handleFor(plugin.robotNamespace());
  std::string prefix;
  switch (plugin.tfPrefixRule()) {
    case TfPrefixRule::kSearched: {  // tf::getPrefixParam
      std::string key;
      if (handle.searchParam("tf_prefix", key)) handle.getParam(key, prefix);
      break;
    }
    case TfPrefixRule::kNamespaceParam: handle.getParam("tf_prefix", prefix); break;
    case TfPrefixRule::kNone: break;
  }
  return FramePrefix(prefix, plugin.globalFrames());
}

void RobotAdapter::sendTransform(const geometry_msgs::TransformStamped& transform) {
  const auto [owner, first] = owners_.robot_of.emplace(transform.child_frame_id, robot_name_);
  if (!first && owner->second != robot_name_ &&
      owners_.warned.insert(transform.child_frame_id + " " + robot_name_).second) {
    ROS_WARN("robots [%s] and [%s] both publish frame [%s] on /tf: set the tf_prefix parameter in each robot's "
             "namespace (e.g. <param name=\"tf_prefix\" value=\"%s\"/> in its <group ns>), which its plugins "
             "and robot_state_publisher read",
             owner->second.c_str(), robot_name_.c_str(), transform.child_frame_id.c_str(), robot_name_.c_str());
  }
  tf_.sendTransform(transform);
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
  for (auto& [subscriber, publishers] : connections.counted_inputs) publishers->count = subscriber.getNumPublishers();
  for (auto& action : connections.actions) action->sendReports();
}

}  // namespace bullet_sim
