#include "plugins/ros_control/diff_drive_controller.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace bullet_sim {

namespace {

/// The radius of a wheel's link: its first collision, a cylinder or a sphere, as diff_drive_controller reads
/// it.
double collisionRadius(const ModelSpec& model, const JointSpec& joint) {
  const LinkSpec* link = model.link(joint.child);
  if (!link || link->collisions.empty()) {
    throw std::invalid_argument(
        "wheel link [" + joint.child +
        "] has no collision to read wheel_radius from: give it one, or set wheel_radius");
  }
  const Shape& shape = link->collisions.front().shape;
  if (shape.type != Shape::Type::kCylinder && shape.type != Shape::Type::kSphere) {
    throw std::invalid_argument("wheel link [" + joint.child +
                                "] is not modelled as a cylinder or a sphere: set wheel_radius");
  }
  return shape.radius;
}

/// A 6 x 6 covariance with `diagonal` (6 numbers, zeros when absent) on its diagonal.
std::array<double, 36> covariance(const ParameterTree& parameters, const std::string& name) {
  std::array<double, 36> matrix{};
  const std::vector<double> diagonal = parameters.numbers(name);
  if (diagonal.empty()) return matrix;
  if (diagonal.size() != 6)
    throw std::invalid_argument(name + " must be 6 numbers, not " + std::to_string(diagonal.size()));
  for (int i = 0; i < 6; ++i) matrix[i * 7] = diagonal[i];
  return matrix;
}

/// velocity_rolling_window_size: samples, at least 1 (less is 1, as before). ros_controllers allocates the
/// window when the controller loads, so one no machine holds fails there; here the bound is a million.
size_t rollingWindow(const ParameterTree& parameters) {
  constexpr double kMostSamples = 1e6;
  const double window = parameters.number("velocity_rolling_window_size", 10);
  if (!(window <= kMostSamples)) {
    throw std::invalid_argument("velocity_rolling_window_size must be at most 1000000 samples, not " +
                                parameters.describe("velocity_rolling_window_size"));
  }
  return static_cast<size_t>(std::max(1.0, window));
}

}  // namespace

DiffDriveController::DiffDriveController(const ControllerSetup& setup)
    : Controller(setup, interfaceName(JointInterface::kVelocity)),
      odometry_(rollingWindow(setup.parameters)) {
  const ParameterTree& parameters = setup.parameters;
  warnUnread(setup, {"left_wheel", "right_wheel", "wheel_separation", "wheel_radius",
                     "wheel_separation_multiplier", "wheel_radius_multiplier", "left_wheel_radius_multiplier",
                     "right_wheel_radius_multiplier", "publish_rate", "base_frame_id", "odom_frame_id",
                     "enable_odom_tf", "open_loop", "velocity_rolling_window_size",
                     "pose_covariance_diagonal", "twist_covariance_diagonal", "cmd_vel_timeout",
                     "allow_multiple_cmd_vel_publishers", "publish_cmd",
                     "publish_wheel_joint_controller_state", "linear", "angular"});
  readWheels(setup);
  readGeometry(setup);
  const double publish_rate = parameters.number("publish_rate", 50);
  if (!(publish_rate > 0 && std::isfinite(publish_rate))) {
    throw std::invalid_argument("publish_rate must be finite and > 0 [Hz], not " +
                                parameters.describe("publish_rate"));
  }
  publish_period_ = 1 / publish_rate;
  open_loop_ = parameters.flag("open_loop", false);
  cmd_vel_timeout_ = parameters.number("cmd_vel_timeout", cmd_vel_timeout_);
  if (!(cmd_vel_timeout_ >= 0)) {  // NaN would never time out, a negative timeout never drive
    throw std::invalid_argument("cmd_vel_timeout must be >= 0 [s], not " +
                                parameters.describe("cmd_vel_timeout"));
  }
  allow_multiple_publishers_ = parameters.flag("allow_multiple_cmd_vel_publishers", true);
  enable_odom_tf_ = parameters.flag("enable_odom_tf", true);
  publish_cmd_ = parameters.flag("publish_cmd", false);
  linear_limiter_ = SpeedLimiter::fromParameters(parameters.at("linear/x"), "linear/x");
  angular_limiter_ = SpeedLimiter::fromParameters(parameters.at("angular/z"), "angular/z");
  if (parameters.flag("publish_wheel_joint_controller_state", false)) {
    setup.warnings.push_back("controller [" + name() +
                             "]: publish_wheel_joint_controller_state is not simulated: no such topic");
  }
  readOdometryFields(setup);
  ownPorts().addInput<Twist>(
      topic("cmd_vel"), [this](const Twist& twist, double sim_time) { return takeCommand(twist, sim_time); },
      &command_publishers_);
  ownPorts().addOutput(topic("odom"), odom_);
  if (enable_odom_tf_) ownPorts().addOutput("", odom_tf_);
  if (publish_cmd_) ownPorts().addOutput(topic("cmd_vel_out"), command_out_);
}

void DiffDriveController::readWheels(const ControllerSetup& setup) {
  const std::vector<std::string> left = setup.parameters.texts("left_wheel");
  const std::vector<std::string> right = setup.parameters.texts("right_wheel");
  if (left.empty() || right.empty()) {
    throw std::invalid_argument(std::string(left.empty() ? "left_wheel" : "right_wheel") +
                                " is not set: give it a wheel joint's name, or a list of them");
  }
  if (left.size() != right.size()) {
    throw std::invalid_argument("left_wheel has " + std::to_string(left.size()) + " wheels and right_wheel " +
                                std::to_string(right.size()) + ": give each side as many");
  }
  for (const auto& name : left) left_.push_back(&claim(name, JointInterface::kVelocity));
  for (const auto& name : right) right_.push_back(&claim(name, JointInterface::kVelocity));
}

void DiffDriveController::readGeometry(const ControllerSetup& setup) {
  const ParameterTree& parameters = setup.parameters;
  const JointSpec& left = *left_.front()->spec;
  const JointSpec& right = *right_.front()->spec;
  wheel_separation_ = parameters.number("wheel_separation",
                                        (left.origin.translation() - right.origin.translation()).norm());
  wheel_radius_ = parameters.has("wheel_radius") ? parameters.number("wheel_radius", 0)
                                                 : collisionRadius(setup.model, left);
  separation_multiplier_ = parameters.number("wheel_separation_multiplier", 1);
  if (parameters.has("wheel_radius_multiplier")) {
    left_radius_multiplier_ = right_radius_multiplier_ = parameters.number("wheel_radius_multiplier", 1);
  } else {
    left_radius_multiplier_ = parameters.number("left_wheel_radius_multiplier", 1);
    right_radius_multiplier_ = parameters.number("right_wheel_radius_multiplier", 1);
  }
  const double separation = separation_multiplier_ * wheel_separation_;
  const double left_radius = left_radius_multiplier_ * wheel_radius_;
  const double right_radius = right_radius_multiplier_ * wheel_radius_;
  const auto usable = [](double length) { return length > 0 && std::isfinite(length); };
  if (!usable(separation) || !usable(left_radius) || !usable(right_radius)) {
    std::ostringstream why;
    why << "the wheel separation (" << separation << " m) and radii (" << left_radius << ", " << right_radius
        << " m), multipliers included, must be finite and > 0";
    throw std::invalid_argument(why.str());
  }
  odometry_.setWheelParams(separation, left_radius, right_radius);
}

void DiffDriveController::readOdometryFields(const ControllerSetup& setup) {
  const ParameterTree& parameters = setup.parameters;
  Odometry& odometry = odom_.next();
  odometry.frame_id = parameters.text("odom_frame_id", "odom");
  odometry.child_frame_id = parameters.text("base_frame_id", "base_link");
  odometry.pose_covariance = covariance(parameters, "pose_covariance_diagonal");
  odometry.twist_covariance = covariance(parameters, "twist_covariance_diagonal");
  odom_tf_.next().frames = {{odometry.frame_id, odometry.child_frame_id, Eigen::Isometry3d::Identity()}};
}

std::string DiffDriveController::takeCommand(const Twist& twist, double sim_time) {
  if (!running()) return "a cmd_vel for controller [" + name() + "], which is not running";
  if (!allow_multiple_publishers_ && command_publishers_.count > 1) {
    setWheels(0, 0);
    return "a cmd_vel for controller [" + name() + "] from one of " +
           std::to_string(command_publishers_.count) +
           " publishers, with allow_multiple_cmd_vel_publishers false: braking";
  }
  if (!std::isfinite(twist.linear.x()) || !std::isfinite(twist.angular.z())) {
    return "a cmd_vel for controller [" + name() + "] that is not finite";
  }
  received_ = {twist.linear.x(), twist.angular.z(), sim_time};
  return "";
}

void DiffDriveController::starting(double time) {
  setWheels(0, 0);
  last_publish_ = time;
  odometry_.init(time);
}

void DiffDriveController::stopping(double) { setWheels(0, 0); }

void DiffDriveController::onReset() {
  odometry_.resetPose();
  received_ = last0_ = last1_ = Command{};
}

void DiffDriveController::onUpdate(double time, double period) {
  integrateOdometry(time);
  if (last_publish_ + publish_period_ < time) {
    last_publish_ += publish_period_;
    publishOdometry(time);
  }
  const Command command = limitedCommand(time, period);
  if (publish_cmd_) {
    StampedTwist& out = command_out_.next();
    out.stamp = time;
    out.twist.linear.x() = command.linear;
    out.twist.angular.z() = command.angular;
    command_out_.publish();
  }
  const double separation = separation_multiplier_ * wheel_separation_;
  setWheels((command.linear - command.angular * separation / 2) / (left_radius_multiplier_ * wheel_radius_),
            (command.linear + command.angular * separation / 2) / (right_radius_multiplier_ * wheel_radius_));
}

void DiffDriveController::integrateOdometry(double time) {
  if (open_loop_) {
    odometry_.updateOpenLoop(last0_.linear, last0_.angular, time);
    return;
  }
  double left = 0, right = 0;
  for (size_t i = 0; i < left_.size(); ++i) {
    if (std::isnan(left_[i]->position) || std::isnan(right_[i]->position)) return;
    left += left_[i]->position;
    right += right_[i]->position;
  }
  odometry_.update(left / static_cast<double>(left_.size()), right / static_cast<double>(right_.size()),
                   time);
}

void DiffDriveController::publishOdometry(double time) {
  const Eigen::Isometry3d pose = Eigen::Translation3d(odometry_.x(), odometry_.y(), 0) *
                                 Eigen::AngleAxisd(odometry_.heading(), Eigen::Vector3d::UnitZ());
  Odometry& odometry = odom_.next();
  odometry.stamp = time;
  odometry.pose = pose;
  odometry.linear_velocity = Eigen::Vector3d(odometry_.linear(), 0, 0);
  odometry.angular_velocity = Eigen::Vector3d(0, 0, odometry_.angular());
  odom_.publish();
  if (!enable_odom_tf_) return;
  TransformSample& tf = odom_tf_.next();
  tf.stamp = time;
  tf.frames.front().pose = pose;
  odom_tf_.publish();
}

DiffDriveController::Command DiffDriveController::limitedCommand(double time, double period) {
  Command command = received_;
  if (time - command.stamp > cmd_vel_timeout_) command.linear = command.angular = 0;
  command.linear = linear_limiter_.limit(command.linear, last0_.linear, last1_.linear, period);
  command.angular = angular_limiter_.limit(command.angular, last0_.angular, last1_.angular, period);
  last1_ = last0_;
  last0_ = command;
  return command;
}

void DiffDriveController::setWheels(double left, double right) {
  for (auto* wheel : left_) wheel->command = left;
  for (auto* wheel : right_) wheel->command = right;
}

}  // namespace bullet_sim
