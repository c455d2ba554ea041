#include "messages.h"

#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>

#include "trajectory_messages.h"

namespace bullet_sim {

FramePrefix::FramePrefix(std::string prefix, std::set<std::string> global_frames)
    : prefix_(withoutSlashes(prefix)), global_frames_(std::move(global_frames)) {}

std::string FramePrefix::operator()(const std::string& frame) const {
  const std::string bare = withoutSlashes(frame);
  if (prefix_.empty() || global_frames_.count(bare)) return bare;
  return prefix_ + "/" + bare;
}

FramePrefix framePrefixOf(const ros::NodeHandle& handle, const Plugin& plugin) {
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

std_msgs::Header header(double stamp, const std::string& frame_id) {
  std_msgs::Header header;
  header.stamp = ros::Time(stamp);
  header.frame_id = frame_id;
  return header;
}

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

namespace {

geometry_msgs::Wrench toMessage(const ContactsSample::Wrench& wrench) {
  geometry_msgs::Wrench message;
  tf2::toMsg(wrench.force, message.force);
  tf2::toMsg(wrench.torque, message.torque);
  return message;
}

}  // namespace

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

sensor_msgs::CameraInfo toMessage(const CameraInfo& info, const FramePrefix& frames) {
  sensor_msgs::CameraInfo message;
  message.header = header(info.stamp, frames(info.frame_id));
  message.width = info.width;
  message.height = info.height;
  message.distortion_model = info.distortion_model;
  message.D.assign(info.D.begin(), info.D.end());
  std::copy(info.K.begin(), info.K.end(), message.K.begin());
  std::copy(info.R.begin(), info.R.end(), message.R.begin());
  std::copy(info.P.begin(), info.P.end(), message.P.begin());
  return message;
}

tf2_msgs::TFMessage toMessage(const TransformSample& sample, const FramePrefix& frames) {
  tf2_msgs::TFMessage message;
  for (const auto& frame : sample.frames) {
    geometry_msgs::TransformStamped& transform =
        message.transforms.emplace_back(tf2::eigenToTransform(frame.pose));
    transform.header = header(sample.stamp, frames(frame.parent));
    transform.child_frame_id = frames(frame.child);
  }
  return message;
}

geometry_msgs::Twist toMessage(const Twist& twist) {
  geometry_msgs::Twist message;
  tf2::toMsg(twist.linear, message.linear);
  tf2::toMsg(twist.angular, message.angular);
  return message;
}

}  // namespace bullet_sim
