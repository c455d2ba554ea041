#include "plugins/force_based_move/force_based_move.h"

#include "bullet_sim/plugins/registry.h"

#include <cmath>

#include "bullet_sim/model/gazebo_names.h"
#include "bullet_sim/model/model_geometry.h"

namespace bullet_sim {

namespace {

/// The centre of mass [m], in `link`'s frame, of the links Gazebo lumps together with it.
Eigen::Vector3d lumpedCentreOfMass(const ModelSpec& model, const std::string& link) {
  const auto poses = linkPosesAtZero(model);
  const std::string lumped = gazeboLink(model, link);
  const Eigen::Isometry3d to_link = poses.at(link).inverse();
  double mass = 0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& other : model.links) {
    if (!other.inertial || gazeboLink(model, other.name) != lumped) continue;
    mass += other.inertial->mass;
    moment += other.inertial->mass * (to_link * poses.at(other.name) * other.inertial->com);
  }
  return mass > 0 ? Eigen::Vector3d(moment / mass) : Eigen::Vector3d::Zero();
}

}  // namespace

TagTable forceBasedMoveTags() {
  TagTable table = holonomicTags();
  const auto gain = [](const std::string& tag, const std::string& fallback, const std::string& unit,
                       const std::string& what) {
    return TagRow{tag, TagType::kPositive, fallback, unit, what, ""};
  };
  for (const TagRow& row : std::vector<TagRow>{
           {"robotBaseFrame", TagType::kFrame, "base_footprint", "",
            "the link the force and torque act on, and the odometry's child_frame_id",
            "an error when it names no link"},
           gain("x_velocity_p_gain", "10000", "N s/m",
                "the force along the base's x per m/s of velocity error"),
           gain("y_velocity_p_gain", "10000", "N s/m",
                "the force along the base's y per m/s of velocity error"),
           gain("yaw_velocity_p_gain", "100", "N m s",
                "the torque about the world's z per rad/s of turn error"),
           {"publishOdometryTf", TagType::kFlag, "true", "",
            "the odometry's tf (odometryFrame to robotBaseFrame)", ""},
       }) {
    table.add(row);
  }
  return table;
}

void parseForceBasedMove(const DeclarationSource& source, ForceBasedMoveConfig& config) {
  PluginTags& tags = source.tags;
  readHolonomicTags(source, config);
  config.yaw_gain = tags.nonNegative("yaw_velocity_p_gain");
  config.x_gain = tags.nonNegative("x_velocity_p_gain");
  config.y_gain = tags.nonNegative("y_velocity_p_gain");
  config.publish_odometry_tf = tags.flag("publishOdometryTf");
  if (source.model.link(config.robot_base_frame)) {
    config.centre_of_mass = lumpedCentreOfMass(source.model, config.robot_base_frame);
  } else {
    const std::string& base = config.robot_base_frame;
    source.diagnostics.error(tags.where() + " <robotBaseFrame> [" + base + "] is not a link" +
                             didYouMean(base, source.model.linkNames()) + "; the forces act on that link");
  }
}

Eigen::Isometry3d motionOver(double x, double y, double yaw_rate, double seconds) {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  const double dx = x * seconds, dy = y * seconds, turn = yaw_rate * seconds;
  if (std::abs(yaw_rate) < 1e-4) {
    motion.translation() = Eigen::Vector3d(dx, dy, 0);
    return motion;
  }
  motion.linear() = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  if (std::abs(dx) < 1e-4 && std::abs(dy) < 1e-4) return motion;  // turning on the spot
  const double radius = std::hypot(dx, dy) / turn;
  const Eigen::Vector3d end(std::sin(turn) * radius, radius - std::cos(turn) * radius, 0);
  motion.translation() = Eigen::AngleAxisd(std::atan2(dy, dx), Eigen::Vector3d::UnitZ()) * end;
  return motion;
}

ForceBasedMove::ForceBasedMove(const PluginDeclaration& declaration, const ForceBasedMoveConfig& config,
                               const PluginSetup& setup)
    : PlanarMove(declaration, config, setup), config_(config) {}

void ForceBasedMove::applyCommands(const StepTime& time, RobotBody& body) {
  const Eigen::Vector3d wanted = command(time.sim_time).cwiseMin(config_.command_cap);
  const std::string& root = body.spec().root;
  const Eigen::Matrix3d root_axes = body.linkPose(root).linear();
  const Eigen::Vector3d velocity = root_axes.transpose() * body.linkLinearVelocity(root);
  const double turn_error = body.linkAngularVelocity(root).z() - wanted.z();
  const Eigen::Isometry3d base = body.linkPose(config_.robot_base_frame);
  const Eigen::Vector3d push((wanted.x() - velocity.x()) * config_.x_gain,
                             (wanted.y() - velocity.y()) * config_.y_gain, 0);  // in the base frame
  const Eigen::Vector3d force = base.linear() * push;
  // Gazebo pushes at the centre of mass; the wrench is taken at the link's origin.
  const Eigen::Vector3d lever = base.linear() * config_.centre_of_mass;
  const Eigen::Vector3d torque(0, 0, -turn_error * config_.yaw_gain);
  body.applyLinkWrench(config_.robot_base_frame, force, torque + lever.cross(force));
}

void ForceBasedMove::fillOdometry(Odometry& odometry, const RobotBody& body, double elapsed) {
  const std::string& root = body.spec().root;
  const Eigen::Matrix3d to_root = body.linkPose(root).linear().transpose();
  const Eigen::Vector3d velocity = to_root * body.linkLinearVelocity(root);
  const Eigen::Vector3d turn = to_root * body.linkAngularVelocity(root);
  odometry_pose_ = odometry_pose_ * motionOver(velocity.x(), velocity.y(), turn.z(), elapsed);
  odometry.pose = odometry_pose_;
  odometry.linear_velocity = {velocity.x(), velocity.y(), 0};
  odometry.angular_velocity = {0, 0, turn.z()};
  // hector's covariances: the yaw is trusted only while the robot does not turn.
  const double yaw_variance = std::abs(turn.z()) < 1e-4 ? 0.01 : 100;
  odometry.pose_covariance = {};
  odometry.twist_covariance = {};
  for (int i : {0, 7}) odometry.pose_covariance[i] = odometry.twist_covariance[i] = 0.001;
  odometry.twist_covariance[14] = 0.001;
  odometry.pose_covariance[14] = 1e12;
  for (int i : {21, 28}) odometry.pose_covariance[i] = odometry.twist_covariance[i] = 1e12;
  odometry.pose_covariance[35] = odometry.twist_covariance[35] = yaw_variance;
}

void ForceBasedMove::onReset() {
  PlanarMove::onReset();
  odometry_pose_ = Eigen::Isometry3d::Identity();
}

// hector_gazebo_plugins' force-based move.
BULLET_SIM_PLUGIN_FOLDER(force_based_move) {
  registrar.add(pluginType<ForceBasedMove>("libgazebo_ros_force_based_move.so", parseForceBasedMove,
                                           forceBasedMoveTags()));
}

}  // namespace bullet_sim
