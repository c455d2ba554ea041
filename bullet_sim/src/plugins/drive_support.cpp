#include "bullet_sim/plugins/drive_support.h"

#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace bullet_sim {

namespace {

/// The text of the first of `names` present, else the first's default in the table; every one present counts
/// as read.
std::string firstText(PluginTags& tags, const std::vector<std::string>& names) {
  std::optional<std::string> value;
  for (const auto& name : names) {
    if (!tags.has(name)) continue;
    const std::string text = tags.text(name);
    if (!value) value = text;
  }
  return value ? *value : tags.text(names.front());
}

/// firstText for frames (see PluginTags::frame).
std::string firstFrame(PluginTags& tags, const std::vector<std::string>& names) {
  std::optional<std::string> value;
  for (const auto& name : names) {
    if (!tags.has(name)) continue;
    const std::string frame = tags.frame(name, "");
    if (!value) value = frame;
  }
  return value ? *value : tags.frame(names.front(), tableDefault(tags, names.front()));
}

}  // namespace

std::string tableDefault(const PluginTags& tags, const std::string& tag) {
  const TagRow* row = tags.table() ? tags.table()->row(tag) : nullptr;
  if (!row) throw std::logic_error(tags.where() + " reads <" + tag + ">, which its plugin's tag table lacks");
  return row->fallback;
}

double tableDefaultNumber(const PluginTags& tags, const std::string& tag) {
  const std::string text = tableDefault(tags, tag);
  try {
    return std::stod(text);
  } catch (const std::exception&) {
    throw std::logic_error(tags.where() + " <" + tag + ">'s table default [" + text + "] is no number");
  }
}

std::optional<std::string> driveWheelModel(const PluginDeclaration& declaration) {
  return declaration.configAs<DriveConfigHead>()->wheel_model;
}

std::vector<TagRow> ownDriveTagRows() {
  return {
      {"commandTimeout", TagType::kPositive, "0", "s", "not read (bullet_sim's tag)",
       "the robot stops once cmd_vel has been silent this long; 0: the last command holds for ever, as in "
       "Gazebo"},
      {"wheelModel", TagType::kText, kDefaultWheelModel, "", "not read (bullet_sim's tag)",
       "the robot's wheel-ground model: raycast (one body, a ray per wheel) or contact (a multibody whose "
       "wheels touch the ground)"},
  };
}

void readDriveHead(PluginTags& tags, const DriveTagNames& names, DriveConfigHead& head) {
  head.command_topic = firstText(tags, names.command_topic);
  head.odometry_topic = firstText(tags, names.odometry_topic);
  head.odometry_frame = firstFrame(tags, names.odometry_frame);
  head.robot_base_frame = firstFrame(tags, names.robot_base_frame);
  head.command_timeout = tags.nonNegative("commandTimeout");
  head.wheel_model = tags.text("wheelModel");
  if (head.wheel_model != "contact" && head.wheel_model != "raycast") {
    tags.diagnostics().error(tags.where() + " <wheelModel> must be contact or raycast, not [" +
                             head.wheel_model + "]");
    head.wheel_model = kDefaultWheelModel;
  }
}

void readPlanarCovariance(PluginTags& tags, DriveConfigHead& head) {
  const double x = tags.nonNegative("covariance_x");
  const double y = tags.nonNegative("covariance_y");
  const double yaw = tags.nonNegative("covariance_yaw");
  head.pose_covariance = head.twist_covariance = planarCovariance(x, y, yaw);
}

std::string vectorText(const Eigen::Vector3d& v) {
  std::ostringstream text;
  text << v.x() << ' ' << v.y() << ' ' << v.z();
  return text.str();
}

std::array<double, 36> planarCovariance(double x, double y, double yaw) {
  std::array<double, 36> covariance{};
  covariance[0] = x;
  covariance[7] = y;
  covariance[14] = covariance[21] = covariance[28] = 1e12;
  covariance[35] = yaw;
  return covariance;
}

double wheelRollSign(const std::map<std::string, Eigen::Isometry3d>& poses, const std::string& base_frame,
                     const JointSpec& joint) {
  const auto base = poses.find(base_frame);
  const Eigen::Matrix3d to_base =
      base == poses.end() ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(base->second.linear().transpose());
  const Eigen::Vector3d axis = to_base * poses.at(joint.child).linear() * joint.axis;
  return axis.y() >= 0 ? 1.0 : -1.0;
}

bool VelocityCommand::set(double linear, double angular, double sim_time) {
  if (!std::isfinite(linear) || !std::isfinite(angular)) return false;
  linear_ = linear;
  angular_ = angular;
  command_time_ = sim_time;
  return true;
}

DrivePlugin::DrivePlugin(const PluginDeclaration& declaration, const DriveConfigHead& head,
                         const PluginSetup& setup)
    : Plugin(declaration, setup), base_frame_(head.base_link), command_(head.command_timeout) {
  Odometry& odometry = odometry_.next();
  odometry.frame_id = head.odometry_frame;
  odometry.child_frame_id = head.robot_base_frame;
  odometry.pose_covariance = head.pose_covariance;
  odometry.twist_covariance = head.twist_covariance;
  odometry_tf_.next().frames = {{head.odometry_frame, head.robot_base_frame, Eigen::Isometry3d::Identity()}};
  addInput<Twist>(head.command_topic, [this](const Twist& twist, double sim_time) -> std::string {
    if (setCommand(twist.linear.x(), twist.angular.z(), sim_time)) return "";
    std::ostringstream why;
    why << "a cmd_vel that is not finite (linear.x " << twist.linear.x() << ", angular.z "
        << twist.angular.z() << ")";
    return why.str();
  });
  if (head.publish_odometry) addOutput(head.odometry_topic, odometry_);
  if (head.publish_odom_tf) addOutput("", odometry_tf_);
}

bool DrivePlugin::setCommand(double linear, double angular, double sim_time) {
  return command_.set(linear, angular, sim_time);
}

void DrivePlugin::publishOdometry() {
  odometry_.publish();
  TransformSample& tf = odometry_tf_.next();
  tf.stamp = odometry_.latest().stamp;
  tf.frames.front().pose = odometry_.latest().pose;
  odometry_tf_.publish();
}

void DrivePlugin::fillGroundTruth(const RobotBody& body, double stamp) {
  Odometry& odometry = odometry_.next();
  const Eigen::Isometry3d base = body.linkPose(base_frame_);
  const Eigen::Matrix3d to_base = base.linear().transpose();
  odometry.stamp = stamp;
  odometry.pose = base;
  odometry.linear_velocity = to_base * body.linkLinearVelocity(base_frame_);
  odometry.angular_velocity = to_base * body.linkAngularVelocity(base_frame_);
}

void DrivePlugin::onReset() {
  command_.reset();
  odometry_.next().stamp = 0;
}

}  // namespace bullet_sim
