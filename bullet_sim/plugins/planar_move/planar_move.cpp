#include "plugins/planar_move/planar_move.h"

#include "bullet_sim/plugins/registry.h"

#include <cmath>
#include <sstream>

#include "bullet_sim/plugins/drive_support.h"

namespace bullet_sim {

namespace {

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); }

TagTable planarMoveTags() {
  TagTable table = holonomicTags();
  table.add(
      {"cmdTimeout", TagType::kNumber, "-1", "s",
       "the robot stops once cmd_vel has been silent this long; below 0: the last command holds for ever",
       ""});
  return table;
}

}  // namespace

TagTable holonomicTags() {
  return {
      {"commandTopic", TagType::kTopic, "cmd_vel", "",
       "the geometry_msgs/Twist it follows: linear.x and linear.y [m/s], angular.z [rad/s]", ""},
      {"odometryTopic", TagType::kTopic, "odom", "", "the topic of its nav_msgs/Odometry", ""},
      {"odometryFrame", TagType::kFrame, "odom", "",
       "the odometry's frame_id, and the parent frame of its tf", ""},
      {"robotBaseFrame", TagType::kFrame, "base_footprint", "",
       "the odometry's child_frame_id; the pose is the model's",
       "the pose is this link's; when it names no link, a warning, and the root link's"},
      {"odometryRate", TagType::kNumber, "20", "Hz",
       "how often the odometry and its tf are published; 0 or less: never", ""},
      {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
  };
}

void readHolonomicTags(const DeclarationSource& source, HolonomicConfig& config) {
  PluginTags& tags = source.tags;
  config.command_topic = tags.text("commandTopic");
  config.odometry_topic = tags.text("odometryTopic");
  config.odometry_frame = tags.frame("odometryFrame", tableDefault(tags, "odometryFrame"));
  config.robot_base_frame = tags.frame("robotBaseFrame", tableDefault(tags, "robotBaseFrame"));
  config.update_rate = tags.number("odometryRate");
}

void parsePlanarMove(const DeclarationSource& source, PlanarMoveConfig& config) {
  readHolonomicTags(source, config);
  config.command_timeout = source.tags.number("cmdTimeout");
  frameLink(source, "robotBaseFrame", config.robot_base_frame, source.model.root);
}

PlanarMove::PlanarMove(const PluginDeclaration& declaration, const HolonomicConfig& config,
                       const PluginSetup& setup)
    : Plugin(declaration, setup),
      config_(config),
      pose_link_(setup.body.spec().link(config.robot_base_frame) ? config.robot_base_frame
                                                                  : setup.body.spec().root) {
  Odometry& odometry = odometry_.next();
  odometry.frame_id = config_.odometry_frame;
  odometry.child_frame_id = config_.robot_base_frame;
  odometry_tf_.next().frames = {
      {config_.odometry_frame, config_.robot_base_frame, Eigen::Isometry3d::Identity()}};
  addInput<Twist>(config_.command_topic, [this](const Twist& twist, double sim_time) -> std::string {
    if (setCommand(twist, sim_time)) return "";
    std::ostringstream why;
    why << "a cmd_vel that is not finite (linear " << twist.linear.transpose() << ", angular.z "
        << twist.angular.z() << ")";
    return why.str();
  });
  // Gazebo publishes odometry (and its tf) only at a positive rate.
  if (config_.update_rate > 0) {
    addOutput(config_.odometry_topic, odometry_);
    if (config_.publish_odometry_tf) addOutput("", odometry_tf_);
  }
  last_pose_ = basePose(setup.body);
}

bool PlanarMove::setCommand(const Twist& command, double sim_time) {
  const Eigen::Vector3d planar(command.linear.x(), command.linear.y(), command.angular.z());
  if (!planar.allFinite()) return false;
  command_ = planar;
  command_time_ = sim_time;
  return true;
}

Eigen::Vector3d PlanarMove::command(double sim_time) const {
  const bool timed_out = config_.command_timeout >= 0 && sim_time - command_time_ > config_.command_timeout;
  return timed_out ? Eigen::Vector3d::Zero() : command_;
}

Eigen::Isometry3d PlanarMove::basePose(const RobotBody& body) const { return body.linkPose(pose_link_); }

void PlanarMove::applyCommands(const StepTime& time, RobotBody& body) {
  const Eigen::Vector3d wanted = command(time.sim_time);
  const double yaw = yawOf(body.linkPose(body.spec().root));
  const Eigen::Vector3d linear(wanted.x() * std::cos(yaw) - wanted.y() * std::sin(yaw),
                               wanted.y() * std::cos(yaw) + wanted.x() * std::sin(yaw), 0);
  body.setRootVelocity(linear, Eigen::Vector3d(0, 0, wanted.z()));
}

void PlanarMove::fillOdometry(Odometry& odometry, const RobotBody& body, double elapsed) {
  const Eigen::Isometry3d pose = basePose(body);
  const double yaw = yawOf(pose);
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // in the world
  double turn_rate = 0;
  if (last_pose_ && elapsed > 0) {
    velocity = (pose.translation() - last_pose_->translation()).head<2>() / elapsed;
    turn_rate = std::remainder(yaw - yawOf(*last_pose_), 2 * M_PI) / elapsed;
  }
  // Gazebo's rule: a turn faster than half a turn per odometry period cannot be told from the poses.
  if (command_.z() > M_PI / elapsed) turn_rate = command_.z();
  last_pose_ = pose;
  odometry.pose = pose;
  odometry.linear_velocity = {std::cos(yaw) * velocity.x() + std::sin(yaw) * velocity.y(),
                              std::cos(yaw) * velocity.y() - std::sin(yaw) * velocity.x(), 0};
  odometry.angular_velocity = {0, 0, turn_rate};
  odometry.pose_covariance = planarCovariance(1e-5, 1e-5, 1e-3);
}

void PlanarMove::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (config_.update_rate <= 0 || !timer().due(time)) return;
  Odometry& odometry = odometry_.next();
  fillOdometry(odometry, body, time.sim_time - last_odometry_);
  last_odometry_ = odometry.stamp = time.sim_time;
  odometry_.publish();
  TransformSample& tf = odometry_tf_.next();
  tf.stamp = odometry.stamp;
  tf.frames.front().pose = odometry.pose;
  odometry_tf_.publish();
}

void PlanarMove::onReset() {
  command_.setZero();
  command_time_ = last_odometry_ = 0;
  last_pose_.reset();
}

BULLET_SIM_PLUGIN_FOLDER(planar_move) {
  registrar.add(pluginType<PlanarMove>("libgazebo_ros_planar_move.so", parsePlanarMove, planarMoveTags()));
}

}  // namespace bullet_sim
