// Each plugin output type as its ROS message, in one place: what the node publishes and the bag recorder
// writes. Frame names go through the plugin's FramePrefix.
#pragma once

#include <control_msgs/JointControllerState.h>
#include <control_msgs/JointTrajectoryControllerState.h>
#include <gazebo_msgs/ContactsState.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/Vector3Stamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/Range.h>
#include <std_msgs/Header.h>
#include <tf2_msgs/TFMessage.h>

#include <set>
#include <string>

#include "bullet_sim/common/names.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

/// Frame names as a plugin publishes them, tf::resolve(tf_prefix, frame) as Noetic's gazebo_plugins name
/// them: without leading or trailing '/', and under the tf_prefix unless the frame was written global
/// ("/odom").
class FramePrefix {
 public:
  explicit FramePrefix(std::string prefix = "", std::set<std::string> global_frames = {});
  std::string operator()(const std::string& frame) const;

 private:
  std::string prefix_;
  std::set<std::string> global_frames_;
};

/// The tf_prefix of `plugin`'s frames, read by its type's rule (TfPrefixRule) from the parameter server,
/// where `handle` is the plugin's namespace.
FramePrefix framePrefixOf(const ros::NodeHandle& handle, const Plugin& plugin);

/// A header stamped `stamp` [s of sim time].
std_msgs::Header header(double stamp, const std::string& frame_id);

nav_msgs::Odometry toMessage(const Odometry& odometry, const FramePrefix& frames);
sensor_msgs::JointState toMessage(const JointStateSample& states, const FramePrefix& frames);
sensor_msgs::LaserScan toMessage(const LaserScan& scan, const FramePrefix& frames);
/// The velodyne driver's layout: x y z intensity (float32) and ring (uint16).
sensor_msgs::PointCloud2 toMessage(const PointCloud& cloud, const FramePrefix& frames);
sensor_msgs::PointCloud toMessage(const LegacyPointCloud& cloud, const FramePrefix& frames);
sensor_msgs::Imu toMessage(const ImuSample& sample, const FramePrefix& frames);
sensor_msgs::Image toMessage(const CameraImage& image, const FramePrefix& frames);
/// gazebo_ros_openni_kinect's layout: x y z (float32) and rgb (packed in a float32), width x height.
sensor_msgs::PointCloud2 toMessage(const ColouredCloud& cloud, const FramePrefix& frames);
sensor_msgs::Range toMessage(const RangeSample& sample, const FramePrefix& frames);
sensor_msgs::NavSatFix toMessage(const NavSatFixSample& fix, const FramePrefix& frames);
geometry_msgs::Vector3Stamped toMessage(const Vector3Sample& sample, const FramePrefix& frames);
gazebo_msgs::ContactsState toMessage(const ContactsSample& contacts, const FramePrefix& frames);
control_msgs::JointControllerState toMessage(const JointControllerState& state, const FramePrefix& frames);
control_msgs::JointTrajectoryControllerState toMessage(const JointTrajectoryControllerState& state,
                                                      const FramePrefix& frames);
geometry_msgs::TwistStamped toMessage(const StampedTwist& twist, const FramePrefix& frames);
/// The camera's calibration as the plugin gives it (the node's camera_info_manager may have another).
sensor_msgs::CameraInfo toMessage(const CameraInfo& info, const FramePrefix& frames);
/// The transforms as /tf carries them, one per frame, all of the sample's stamp.
tf2_msgs::TFMessage toMessage(const TransformSample& sample, const FramePrefix& frames);
/// A velocity command as cmd_vel carries it.
geometry_msgs::Twist toMessage(const Twist& twist);

}  // namespace bullet_sim
