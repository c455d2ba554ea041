#include "bullet_sim/plugins/wheeled_drive.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "bullet_sim/spec/model_geometry.h"

namespace bullet_sim {

namespace {

constexpr double kGeometryTolerance = 0.005;  // [m] plugin figures vs URDF geometry before we say so

/// Gazebo's diff-drive pose covariance: tight in x, y and yaw, unknown (1e12) in z, roll and pitch.
std::array<double, 36> planarCovariance(double xy, double yaw) {
  std::array<double, 36> covariance{};
  covariance[0] = covariance[7] = xy;
  covariance[14] = covariance[21] = covariance[28] = 1e12;
  covariance[35] = yaw;
  return covariance;
}

void readCommon(PluginTags& tags, DriveConfig& config) {
  config.robot_namespace = tags.text("robotNamespace", "");
  config.command_topic = tags.text("commandTopic", config.command_topic);
  config.odometry_topic = tags.text("odometryTopic", config.odometry_topic);
  config.odometry_frame = tags.text("odometryFrame", config.odometry_frame);
  config.robot_base_frame = tags.text("robotBaseFrame", config.robot_base_frame);
  config.wheel_separation = tags.positive("wheelSeparation", config.wheel_separation);
  config.wheel_diameter = tags.positive("wheelDiameter", config.wheel_diameter);
  config.update_rate = tags.positive("updateRate", config.update_rate, /*allow_zero=*/true);
  config.command_timeout = tags.positive("commandTimeout", 0.0, /*allow_zero=*/true);
  config.wheel_model = tags.text("wheelModel", config.wheel_model);
  if (config.wheel_model != "contact" && config.wheel_model != "raycast") {
    tags.diagnostics().error(tags.where() + " <wheelModel> must be contact or raycast, not [" +
                             config.wheel_model + "]");
  }
  tags.accept({"rosDebugLevel", "alwaysOn"});
}

}  // namespace

DriveConfig parseDiffDriveConfig(PluginTags& tags) {
  DriveConfig config;
  readCommon(tags, config);
  config.left_joints = {tags.text("leftJoint", "left_joint")};
  config.right_joints = {tags.text("rightJoint", "right_joint")};
  config.torque = tags.positive("wheelTorque", 5.0);
  config.acceleration = tags.positive("wheelAcceleration", 0.0, /*allow_zero=*/true);
  const std::string source = tags.text("odometrySource", "world");
  if (source == "encoder") {
    config.odometry_from_encoders = true;
  } else if (source != "world") {
    tags.diagnostics().warning(tags.where() + " <odometrySource> must be world or encoder, not [" + source +
                               "]: world is used, as Gazebo does");
  }
  config.publish_odometry = tags.flag("publishTf", true);
  config.publish_odom_tf = tags.flag("publishOdomTF", true);
  config.publish_wheel_tf = tags.flag("publishWheelTF", false);
  config.publish_wheel_joint_state = tags.flag("publishWheelJointState", false);
  if (tags.has("legacyMode")) {
    tags.flag("legacyMode", false);
    tags.diagnostics().warning(
        tags.where() +
        " <legacyMode> is a Kinetic tag (it swapped the wheels): ignored; REP 103 is followed");
  }
  config.pose_covariance = planarCovariance(1e-5, 1e-3);
  config.twist_covariance = planarCovariance(1e-5, 1e-3);
  return config;
}

DriveConfig parseSkidSteerConfig(PluginTags& tags) {
  DriveConfig config;
  config.wheel_separation = 0.4;
  readCommon(tags, config);
  config.left_joints = {tags.text("leftFrontJoint", "left_front_joint"),
                        tags.text("leftRearJoint", "left_rear_joint")};
  config.right_joints = {tags.text("rightFrontJoint", "right_front_joint"),
                         tags.text("rightRearJoint", "right_rear_joint")};
  config.torque = tags.positive("torque", 5.0);
  config.publish_odom_tf = tags.flag("broadcastTF", false);
  const double xy = tags.positive("covariance_x", 1e-4, true);
  const double y = tags.positive("covariance_y", 1e-4, true);
  const double yaw = tags.positive("covariance_yaw", 0.01, true);
  config.pose_covariance = planarCovariance(xy, yaw);
  config.pose_covariance[7] = y;
  config.twist_covariance = config.pose_covariance;
  return config;
}

WheeledDrive::WheeledDrive(std::string name, DriveConfig config, const ModelSpec& model,
                           const RobotBody& body, Diagnostics& diagnostics)
    : Plugin(std::move(name)),
      config_(std::move(config)),
      timer_(config_.update_rate),
      command_(config_.command_timeout) {
  const std::string where = "plugin [" + this->name() + "]";
  const auto poses = linkPosesAtZero(model);
  if (!model.link(config_.robot_base_frame)) {
    diagnostics.error(where + " <robotBaseFrame> [" + config_.robot_base_frame + "] is not a link" +
                      didYouMean(config_.robot_base_frame, model.linkNames()));
    return;
  }
  const Eigen::Isometry3d base = poses.at(config_.robot_base_frame);

  // Where each wheel sits across the base [m], to check wheelSeparation against the URDF.
  std::vector<double> left_y, right_y;
  const auto addWheels = [&](const std::vector<std::string>& names, std::vector<Wheel>& wheels,
                             std::vector<double>& lateral) {
    for (const auto& joint_name : names) {
      const JointSpec* joint = model.joint(joint_name);
      if (!joint || !joint->moves()) {
        diagnostics.error(where + " names joint [" + joint_name + "], which " +
                          (joint ? "is fixed: wheels need continuous joints" : "does not exist") +
                          (joint ? "" : didYouMean(joint_name, model.jointNames())));
        continue;
      }
      Wheel wheel;
      wheel.joint = body.jointIndex(joint_name);
      const Eigen::Isometry3d in_base = base.inverse() * poses.at(joint->child);
      const Eigen::Vector3d axis = in_base.linear() * joint->axis;
      // Spinning about +y (the base's left) rolls a wheel forward: its contact point moves backwards.
      wheel.sign = axis.y() >= 0 ? 1.0 : -1.0;
      if (wheel.sign < 0) {
        std::ostringstream axis_text;
        axis_text << joint->axis.x() << ' ' << joint->axis.y() << ' ' << joint->axis.z();
        diagnostics.warning(
            where + " joint [" + joint_name + "] turns about " + axis_text.str() +
            ", against the other side: it is driven with the opposite sign so the robot rolls "
            "forward (Gazebo would spin it in place)");
      }
      if (const LinkSpec* link = model.link(joint->child); link && !link->collisions.empty()) {
        const Shape& shape = link->collisions.front().shape;
        if ((shape.type == Shape::Type::kCylinder || shape.type == Shape::Type::kSphere) &&
            std::abs(2 * shape.radius - config_.wheel_diameter) > kGeometryTolerance) {
          std::ostringstream message;
          message << where << " <wheelDiameter> " << config_.wheel_diameter << " m disagrees with link ["
                  << link->name << "], whose collision is " << 2 * shape.radius << " m across";
          diagnostics.warning(message.str());
        }
      }
      lateral.push_back(in_base.translation().y());
      wheels.push_back(wheel);
    }
  };
  addWheels(config_.left_joints, left_, left_y);
  addWheels(config_.right_joints, right_, right_y);
  for (size_t i = 0; i < std::min(left_y.size(), right_y.size()); ++i) {
    const double separation = left_y[i] - right_y[i];
    if (std::abs(separation - config_.wheel_separation) > kGeometryTolerance) {
      std::ostringstream message;
      message << where << " <wheelSeparation> " << config_.wheel_separation
              << " m disagrees with the joints [" << config_.left_joints[i] << "] and ["
              << config_.right_joints[i] << "], which are " << separation << " m apart";
      diagnostics.warning(message.str());
    }
  }
  for (const auto& names : {config_.left_joints, config_.right_joints}) {
    wheel_states_.names.insert(wheel_states_.names.end(), names.begin(), names.end());
  }
  odometry_.frame_id = config_.odometry_frame;
  odometry_.child_frame_id = config_.robot_base_frame;
  odometry_.pose_covariance = config_.pose_covariance;
  odometry_.twist_covariance = config_.twist_covariance;
}

bool WheeledDrive::setCommand(double linear, double angular, double sim_time) {
  return command_.set(linear, angular, sim_time);
}

void WheeledDrive::applyCommands(const StepTime& time, RobotBody& body) {
  updated_this_step_ = timer_.due(time);
  if (!updated_this_step_) return;
  const double elapsed = time.sim_time - last_update_;
  last_update_ = time.sim_time;

  const double linear = command_.linear(time.sim_time);
  const double angular = command_.angular(time.sim_time);
  const double radius = config_.wheel_diameter / 2;
  const auto drive = [&](std::vector<Wheel>& wheels, double target) {
    for (auto& wheel : wheels) {
      if (config_.acceleration > 0) {
        const double step = config_.acceleration * elapsed;
        wheel.rim_speed += std::clamp(target - wheel.rim_speed, -step, step);
      } else {
        wheel.rim_speed = target;
      }
      body.setJointVelocity(wheel.joint, wheel.sign * wheel.rim_speed / radius, config_.torque);
    }
  };
  drive(left_, linear - angular * config_.wheel_separation / 2);
  drive(right_, linear + angular * config_.wheel_separation / 2);
}

Eigen::Vector2d WheeledDrive::integrateEncoders(const RobotBody& body) {
  const auto travelled = [&](std::vector<Wheel>& wheels) {
    double sum = 0;
    for (auto& wheel : wheels) {
      const double position = body.jointPosition(wheel.joint);
      sum += wheel.sign * (position - wheel.last_position) * config_.wheel_diameter / 2;
      wheel.last_position = position;
    }
    return sum / wheels.size();
  };
  const double left = travelled(left_);
  const double right = travelled(right_);
  // Midpoint integration of the unicycle (Siegwart), as gazebo_ros_diff_drive's encoder source does.
  const double distance = (left + right) / 2;
  const double turn = (right - left) / config_.wheel_separation;
  encoder_pose_.x() += distance * std::cos(encoder_pose_.z() + turn / 2);
  encoder_pose_.y() += distance * std::sin(encoder_pose_.z() + turn / 2);
  encoder_pose_.z() += turn;
  return {distance, turn};
}

void WheeledDrive::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!updated_this_step_) return;
  const double elapsed = time.sim_time - odometry_.stamp;
  odometry_.stamp = time.sim_time;
  if (config_.odometry_from_encoders) {
    const Eigen::Vector2d moved = integrateEncoders(body);  // distance [m], turn [rad]
    odometry_.pose = Eigen::Translation3d(encoder_pose_.x(), encoder_pose_.y(), 0) *
                     Eigen::AngleAxisd(encoder_pose_.z(), Eigen::Vector3d::UnitZ());
    odometry_.linear_velocity = Eigen::Vector3d(moved.x() / elapsed, 0, 0);
    odometry_.angular_velocity = Eigen::Vector3d(0, 0, moved.y() / elapsed);
  } else {
    setGroundTruth(odometry_, body, config_.robot_base_frame, time.sim_time);
  }
  ++odometry_count_;

  if (config_.publish_wheel_joint_state) {
    wheel_states_.stamp = time.sim_time;
    wheel_states_.positions.clear();
    wheel_states_.velocities.clear();
    wheel_states_.efforts.clear();
    for (const auto* wheels : {&left_, &right_}) {
      for (const auto& wheel : *wheels) {
        wheel_states_.positions.push_back(body.jointPosition(wheel.joint));
        wheel_states_.velocities.push_back(body.jointVelocity(wheel.joint));
        wheel_states_.efforts.push_back(body.jointEffort(wheel.joint));
      }
    }
    ++wheel_states_count_;
  }
}

void WheeledDrive::reset() {
  timer_.reset();
  last_update_ = 0;
  command_.reset();
  encoder_pose_.setZero();
  odometry_.stamp = 0;
  for (auto* wheels : {&left_, &right_}) {
    for (auto& wheel : *wheels) wheel.rim_speed = wheel.last_position = 0;
  }
}

}  // namespace bullet_sim
