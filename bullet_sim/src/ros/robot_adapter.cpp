#include "robot_adapter.h"

#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <trajectory_msgs/JointTrajectory.h>

#include "bullet_sim/plugins/ackermann_drive.h"
#include "bullet_sim/plugins/ground_truth.h"
#include "bullet_sim/plugins/imu.h"
#include "bullet_sim/plugins/joint_position.h"
#include "bullet_sim/plugins/joint_states.h"
#include "bullet_sim/plugins/ray_lidar.h"
#include "bullet_sim/plugins/wheeled_drive.h"

namespace bullet_sim {

namespace {

void fill(const Eigen::Isometry3d& pose, geometry_msgs::Pose& out) {
  const Eigen::Quaterniond q(pose.linear());
  out.position.x = pose.translation().x();
  out.position.y = pose.translation().y();
  out.position.z = pose.translation().z();
  out.orientation.x = q.x();
  out.orientation.y = q.y();
  out.orientation.z = q.z();
  out.orientation.w = q.w();
}

void fill(const Eigen::Vector3d& v, geometry_msgs::Vector3& out) {
  out.x = v.x();
  out.y = v.y();
  out.z = v.z();
}

nav_msgs::Odometry toMessage(const Odometry& odometry, const std::string& frame, const std::string& child) {
  nav_msgs::Odometry message;
  message.header.stamp = ros::Time(odometry.stamp);
  message.header.frame_id = frame;
  message.child_frame_id = child;
  fill(odometry.pose, message.pose.pose);
  fill(odometry.linear_velocity, message.twist.twist.linear);
  fill(odometry.angular_velocity, message.twist.twist.angular);
  std::copy(odometry.pose_covariance.begin(), odometry.pose_covariance.end(),
            message.pose.covariance.begin());
  std::copy(odometry.twist_covariance.begin(), odometry.twist_covariance.end(),
            message.twist.covariance.begin());
  return message;
}

sensor_msgs::JointState toMessage(const JointStateSample& states) {
  sensor_msgs::JointState message;
  message.header.stamp = ros::Time(states.stamp);
  message.name = states.names;
  message.position = states.positions;
  message.velocity = states.velocities;
  message.effort = states.efforts;
  return message;
}

std::string withoutSlashes(std::string text) {
  while (!text.empty() && text.front() == '/') text.erase(text.begin());
  while (!text.empty() && text.back() == '/') text.pop_back();
  return text;
}

}  // namespace

template <class Drive>
ros::NodeHandle RobotAdapter::connectDrive(Drive* drive, const DriveTopics& topics) {
  ros::NodeHandle handle = handleFor(topics.robot_namespace);
  if (frame_prefix_.empty()) frame_prefix_ = withoutSlashes(topics.robot_namespace);
  subscribers_.push_back(handle.subscribe<geometry_msgs::Twist>(
      topics.command_topic, 10,
      [this, drive, name = robot_.name()](const geometry_msgs::Twist::ConstPtr& twist) {
        if (!drive->setCommand(twist->linear.x, twist->angular.z, sim_time_())) {
          ROS_WARN_THROTTLE(5, "[%s] ignored a cmd_vel that is not finite (linear.x %f, angular.z %f)",
                            name.c_str(), twist->linear.x, twist->angular.z);
        }
      }));
  topics_.push_back(subscribers_.back().getTopic() + " (in)");
  const std::string odom_frame = frame(topics.odometry_frame);
  const std::string base_frame = frame(topics.robot_base_frame);
  ros::Publisher odom = topics.publish_odometry ? advertise<nav_msgs::Odometry>(handle, topics.odometry_topic)
                                                : ros::Publisher();
  outputs_.push_back({[drive] { return drive->odometryCount(); },
                      [this, drive, odom, odom_frame, base_frame, publish_tf = topics.publish_odom_tf] {
                        const Odometry& odometry = drive->odometry();
                        if (odom) odom.publish(toMessage(odometry, odom_frame, base_frame));
                        if (publish_tf) {
                          geometry_msgs::TransformStamped transform;
                          transform.header.stamp = ros::Time(odometry.stamp);
                          transform.header.frame_id = odom_frame;
                          transform.child_frame_id = base_frame;
                          geometry_msgs::Pose pose;
                          fill(odometry.pose, pose);
                          transform.transform.translation.x = pose.position.x;
                          transform.transform.translation.y = pose.position.y;
                          transform.transform.translation.z = pose.position.z;
                          transform.transform.rotation = pose.orientation;
                          tf_.sendTransform(transform);
                        }
                      }});
  return handle;
}

RobotAdapter::RobotAdapter(Robot& robot, const std::string& robot_namespace,
                           tf2_ros::TransformBroadcaster& tf, std::function<double()> sim_time)
    : robot_(robot), namespace_(withoutSlashes(robot_namespace)), tf_(tf), sim_time_(std::move(sim_time)) {
  frame_prefix_ = namespace_;

  for (WheeledDrive* drive : robot.pluginsOf<WheeledDrive>()) {
    const DriveConfig& config = drive->config();
    ros::NodeHandle handle = connectDrive(
        drive, {config.robot_namespace, config.command_topic, config.odometry_topic, config.odometry_frame,
                config.robot_base_frame, config.publish_odometry, config.publish_odom_tf});
    if (config.publish_wheel_joint_state) {
      ros::Publisher states = advertise<sensor_msgs::JointState>(handle, "joint_states");
      outputs_.push_back({[drive] { return drive->wheelJointStatesCount(); },
                          [drive, states] { states.publish(toMessage(drive->wheelJointStates())); }});
    }
  }

  for (AckermannDrive* drive : robot.pluginsOf<AckermannDrive>()) {
    const AckermannConfig& config = drive->config();
    connectDrive(drive,
                 {config.robot_namespace, config.command_topic, config.odometry_topic, config.odometry_frame,
                  config.robot_base_frame, config.publish_odometry, config.publish_odom_tf});
  }

  for (JointStates* plugin : robot.pluginsOf<JointStates>()) {
    ros::Publisher states =
        advertise<sensor_msgs::JointState>(handleFor(plugin->robotNamespace()), "joint_states");
    outputs_.push_back({[plugin] { return plugin->statesCount(); },
                        [plugin, states] { states.publish(toMessage(plugin->states())); }});
  }

  for (RayLidar* lidar : robot.pluginsOf<RayLidar>()) {
    const RayLidarConfig& config = lidar->config();
    const ros::NodeHandle handle = handleFor(config.robot_namespace);
    const std::string frame_id = frame(config.frame);
    switch (config.output) {
      case RayLidarConfig::Output::kLaserScan: {
        ros::Publisher scans = advertise<sensor_msgs::LaserScan>(handle, config.topic);
        outputs_.push_back({[lidar] { return lidar->scanCount(); },
                            [lidar, scans, frame_id] {
                              const LaserScan& scan = lidar->scan();
                              sensor_msgs::LaserScan message;
                              message.header.stamp = ros::Time(scan.stamp);
                              message.header.frame_id = frame_id;
                              message.angle_min = scan.angle_min;
                              message.angle_max = scan.angle_max;
                              message.angle_increment = scan.angle_increment;
                              message.time_increment = 0;
                              message.scan_time = scan.scan_time;
                              message.range_min = scan.range_min;
                              message.range_max = scan.range_max;
                              message.ranges = scan.ranges;
                              scans.publish(message);
                            }});
        break;
      }
      case RayLidarConfig::Output::kPointCloud2: {
        ros::Publisher clouds = advertise<sensor_msgs::PointCloud2>(handle, config.topic);
        outputs_.push_back({[lidar] { return lidar->scanCount(); },
                            [lidar, clouds, frame_id] {
                              const PointCloud& cloud = lidar->cloud();
                              sensor_msgs::PointCloud2 message;
                              message.header.stamp = ros::Time(cloud.stamp);
                              message.header.frame_id = frame_id;
                              sensor_msgs::PointCloud2Modifier fields(message);
                              // The velodyne driver's layout: x y z intensity (float32) and ring (uint16).
                              fields.setPointCloud2Fields(5, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1,
                                                          sensor_msgs::PointField::FLOAT32, "z", 1,
                                                          sensor_msgs::PointField::FLOAT32, "intensity", 1,
                                                          sensor_msgs::PointField::FLOAT32, "ring", 1,
                                                          sensor_msgs::PointField::UINT16);
                              fields.resize(cloud.points.size());
                              sensor_msgs::PointCloud2Iterator<float> x(message, "x"),
                                  intensity(message, "intensity");
                              sensor_msgs::PointCloud2Iterator<uint16_t> ring(message, "ring");
                              for (size_t i = 0; i < cloud.points.size(); ++i, ++x, ++intensity, ++ring) {
                                x[0] = cloud.points[i].x();
                                x[1] = cloud.points[i].y();
                                x[2] = cloud.points[i].z();
                                *intensity = cloud.intensities[i];
                                *ring = cloud.rings[i];
                              }
                              message.is_dense = true;
                              clouds.publish(message);
                            }});
        break;
      }
      case RayLidarConfig::Output::kPointCloud: {
        ros::Publisher clouds = advertise<sensor_msgs::PointCloud>(handle, config.topic);
        outputs_.push_back({[lidar] { return lidar->scanCount(); },
                            [lidar, clouds, frame_id] {
                              const PointCloud& cloud = lidar->cloud();
                              sensor_msgs::PointCloud message;
                              message.header.stamp = ros::Time(cloud.stamp);
                              message.header.frame_id = frame_id;
                              message.channels.resize(1);
                              message.channels[0].name = "intensity";
                              message.channels[0].values = cloud.intensities;
                              message.points.resize(cloud.points.size());
                              for (size_t i = 0; i < cloud.points.size(); ++i) {
                                message.points[i].x = cloud.points[i].x();
                                message.points[i].y = cloud.points[i].y();
                                message.points[i].z = cloud.points[i].z();
                              }
                              clouds.publish(message);
                            }});
        break;
      }
    }
  }

  for (Imu* imu : robot.pluginsOf<Imu>()) {
    ros::Publisher samples =
        advertise<sensor_msgs::Imu>(handleFor(imu->config().robot_namespace), imu->config().topic);
    const std::string frame_id = frame(imu->config().frame);
    outputs_.push_back({[imu] { return imu->sampleCount(); },
                        [imu, samples, frame_id] {
                          const ImuSample& sample = imu->sample();
                          sensor_msgs::Imu message;
                          message.header.stamp = ros::Time(sample.stamp);
                          message.header.frame_id = frame_id;
                          message.orientation.x = sample.orientation.x();
                          message.orientation.y = sample.orientation.y();
                          message.orientation.z = sample.orientation.z();
                          message.orientation.w = sample.orientation.w();
                          fill(sample.angular_velocity, message.angular_velocity);
                          fill(sample.linear_acceleration, message.linear_acceleration);
                          for (int i : {0, 4, 8}) {
                            message.orientation_covariance[i] = sample.orientation_variance;
                            message.angular_velocity_covariance[i] = sample.angular_velocity_variance;
                            message.linear_acceleration_covariance[i] = sample.linear_acceleration_variance;
                          }
                          samples.publish(message);
                        }});
  }

  for (GroundTruth* truth : robot.pluginsOf<GroundTruth>()) {
    ros::Publisher poses = advertise<nav_msgs::Odometry>(handleFor(truth->robotNamespace()), truth->topic());
    outputs_.push_back({[truth] { return truth->odometryCount(); },
                        [this, truth, poses] {
                          const Odometry& odometry = truth->odometry();
                          poses.publish(
                              toMessage(odometry, odometry.frame_id, frame(odometry.child_frame_id)));
                        }});
  }

  for (JointPosition* holder : robot.pluginsOf<JointPosition>()) {
    subscribers_.push_back(
        handleFor(holder->robotNamespace())
            .subscribe<trajectory_msgs::JointTrajectory>(
                holder->topic(), 10,
                [holder, name = robot.name()](const trajectory_msgs::JointTrajectory::ConstPtr& msg) {
                  if (msg->points.empty()) return;
                  const auto& positions = msg->points.front().positions;
                  for (size_t i = 0; i < msg->joint_names.size() && i < positions.size(); ++i) {
                    if (!holder->setTarget(msg->joint_names[i], positions[i])) {
                      ROS_WARN_THROTTLE(5, "[%s] cannot hold joint [%s] at %f", name.c_str(),
                                        msg->joint_names[i].c_str(), positions[i]);
                    }
                  }
                }));
    topics_.push_back(subscribers_.back().getTopic() + " (in)");
  }
}

ros::NodeHandle RobotAdapter::handleFor(const std::string& plugin_namespace) const {
  const std::string ns = namespace_.empty() ? withoutSlashes(plugin_namespace) : namespace_;
  return ns.empty() ? ros::NodeHandle() : ros::NodeHandle("/" + ns);
}

std::string RobotAdapter::frame(const std::string& name) const {
  const std::string bare = withoutSlashes(name);
  return frame_prefix_.empty() ? bare : frame_prefix_ + "/" + bare;
}

template <class Message>
ros::Publisher RobotAdapter::advertise(ros::NodeHandle handle, const std::string& topic) {
  publishers_.push_back(handle.advertise<Message>(topic, 10));
  topics_.push_back(publishers_.back().getTopic());
  return publishers_.back();
}

void RobotAdapter::publish() {
  for (auto& output : outputs_) {
    const uint64_t count = output.count();
    if (count != output.seen) {
      output.seen = count;
      output.publish();
    }
  }
}

}  // namespace bullet_sim
