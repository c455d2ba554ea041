#include "plugins/ackermann_drive/ackermann_drive.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "bullet_sim/common/names.h"
#include "bullet_sim/model/model_geometry.h"

namespace bullet_sim {

namespace {

constexpr double kGeometryTolerance = 0.005;  // [m] tag figures vs URDF geometry before we say so
constexpr double kMinVerticalAxis = 0.9;      // |z| of a steering axis, as a unit vector in the base frame

/// A ROS 1 spelling of ROS 2's `tag`, which our other drives use: read as it.
TagRow aliasRow(const std::string& tag, const TagRow& ros2) {
  TagRow row = ros2;
  row.name = tag;
  row.gazebo = "not read (the ROS 1 drives' spelling of " + ros2.name + ")";
  row.ours = "read as " + ros2.name + ", which wins when both are given";
  return row;
}

/// The topics, frames and rate, each in ROS 2's spelling and then in ROS 1's.
std::vector<TagRow> headRows() {
  const std::vector<std::pair<TagRow, std::string>> rows = {
      {{"command_topic", TagType::kTopic, "cmd_vel", "",
        "not read: ROS 2's plugin follows cmd_vel, renamed with <ros><remapping>",
        "the geometry_msgs/Twist it follows: linear.x [m/s] and angular.z, a turn rate [rad/s]"},
       "commandTopic"},
      {{"odometry_topic", TagType::kTopic, "odom", "",
        "not read: ROS 2's plugin publishes on odom, renamed with <ros><remapping>",
        "the topic of its nav_msgs/Odometry"},
       "odometryTopic"},
      {{"odometry_frame", TagType::kFrame, "odom", "",
        "the odometry's frame_id, and the parent frame of its tf", ""},
       "odometryFrame"},
      {{"robot_base_frame", TagType::kFrame, "base_footprint", "",
        "the odometry's child_frame_id; the pose is the model's",
        "the pose is this link's, and the URDF's geometry is measured in it; when it names no link, a "
        "warning, and the root link's"},
       "robotBaseFrame"},
      {{"update_rate", TagType::kRate, "100", "Hz",
        "how often the joints get new commands and the odometry is published; 0: every step", ""},
       "updateRate"},
  };
  std::vector<TagRow> head;
  for (const auto& [ros2, ros1] : rows) {
    head.push_back(ros2);
    head.push_back(aliasRow(ros1, ros2));
  }
  return head;
}

std::vector<TagRow> jointRows() {
  const auto joint = [](const std::string& tag, const std::string& gazebo, const std::string& ours) {
    return TagRow{tag, TagType::kText, tag, "", gazebo, ours};
  };
  const std::string front = "rolls freely; it must exist and move";
  const std::string rear =
      "turned by a velocity motor as strong as its URDF effort limit, at the speed an open differential "
      "gives it; it must have an effort limit";
  const std::string steering =
      "held at its Ackermann angle by a position motor as strong as its URDF effort limit; it must turn "
      "about the vertical and have an effort limit";
  return {
      joint("front_left_joint", "the front left wheel's joint, which rolls freely", front),
      joint("front_right_joint", "the front right wheel's joint, which rolls freely", front),
      joint("rear_left_joint", "the rear left wheel's joint, pushed by a PID-controlled force", rear),
      joint("rear_right_joint",
            "the rear right wheel's joint, pushed by a PID-controlled force; its collision's radius is the "
            "wheel radius",
            rear + "; the rear wheels' collision radius is the wheel radius"),
      joint("left_steering_joint", "the left steering hinge, pushed by a PID-controlled force", steering),
      joint("right_steering_joint", "the right steering hinge, pushed by a PID-controlled force", steering),
      joint("steering_wheel_joint", "a steering wheel, set to the tyres' mean angle over the steering ratio",
            "not turned: a warning when the tag is given"),
  };
}

/// The PID gains of ROS 2's joint forces, which our motors have no use for.
std::vector<TagRow> gainRows() {
  const std::string ignored = "read and ignored with a warning: the joints are driven by motors";
  std::vector<TagRow> rows;
  for (const auto& [prefix, force] : {std::pair{"left_steering", "the left steering force"},
                                      std::pair{"right_steering", "the right steering force"},
                                      std::pair{"linear_velocity", "the rear wheels' force"}}) {
    rows.push_back({std::string(prefix) + "_pid_gain", TagType::kList, "0 0 0", "",
                    std::string("the P, I and D gains of ") + force, ignored});
    rows.push_back({std::string(prefix) + "_i_range", TagType::kList, "0 0", "",
                    std::string("the range of the integral term of ") + force, ignored});
  }
  return rows;
}

/// The figures ROS 2's plugin measures in the model, which we read to check them against the URDF.
std::vector<TagRow> figureRows() {
  const auto figure = [](const std::string& tag, const std::string& gazebo, const std::string& what) {
    return TagRow{tag, TagType::kPositive, "the URDF's", "m", gazebo,
                  "optional: a warning when it is more than 5 mm off the URDF's " + what + ", which is used"};
  };
  return {
      figure("wheel_base", "not read: ROS 2's plugin measures it between the axles' wheel centres",
             "rear axle to the steering joints' line"),
      figure("track_width", "not read: ROS 2's plugin measures the front wheels' separation",
             "distance between the rear wheels' joints"),
      figure("wheel_radius", "not read: ROS 2's plugin takes the rear right wheel's collision radius",
             "rear wheels' collision radius"),
  };
}

TagTable ackermannTags() {
  TagTable table;
  const auto add = [&](const std::vector<TagRow>& rows) {
    for (const TagRow& row : rows) table.add(row);
  };
  const auto covariance = [](const std::string& tag, const std::string& fallback, const std::string& of) {
    return TagRow{tag, TagType::kPositive, fallback, "", "the variance of " + of + " in the odometry", ""};
  };
  const std::string not_published = "not published: a warning when true";
  add(headRows());
  add(jointRows());
  add({
      {"max_steer", TagType::kPositive, "0.6", "rad",
       "the largest steering angle, of a virtual wheel between the front two",
       "the largest angle of each tyre, within its joint's limits; it must be below pi/2"},
      {"max_steering_angle", TagType::kIgnored, "7.85", "rad",
       "the steering wheel's largest angle, which only sets its ratio", "no steering wheel is turned"},
      {"max_speed", TagType::kPositive, "20", "m/s", "linear.x is clamped to +-max_speed", ""},
  });
  add(gainRows());
  add({
      {"publish_odom", TagType::kFlag, "false", "", "the odometry: the model's pose in the world",
       "the pose of robot_base_frame in the world"},
      {"publish_odom_tf", TagType::kFlag, "false", "", "the odometry's tf", ""},
      {"publish_wheel_tf", TagType::kFlag, "false", "", "each wheel joint's frame on /tf", not_published},
      {"publish_distance", TagType::kFlag, "false", "",
       "the distance travelled, on distance (std_msgs/Float32)", not_published},
      covariance("covariance_x", "1e-5", "x [m^2]"),
      covariance("covariance_y", "1e-5", "y [m^2]"),
      covariance("covariance_yaw", "1e-3", "the yaw [rad^2]"),
  });
  add(figureRows());
  add({
      {"rosDebugLevel", TagType::kIgnored, "", "", "not read", ""},
      {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
  });
  add(ownDriveTagRows());
  return table;
}

std::optional<double> optionalPositive(PluginTags& tags, const std::string& tag) {
  if (!tags.has(tag)) return std::nullopt;
  return tags.positive(tag, 0.0);
}

/// One warning about ROS 2's tags that change nothing here: the PID gains, the steering wheel and the outputs
/// we do not publish.
void warnOfRos2Extras(PluginTags& tags) {
  // ROS 2's plugin pushes its joints with PID-controlled forces; ours are motors (see the header).
  std::vector<std::string> gains;
  for (const char* tag : {"left_steering_pid_gain", "left_steering_i_range", "right_steering_pid_gain",
                          "right_steering_i_range", "linear_velocity_pid_gain", "linear_velocity_i_range"}) {
    if (!tags.has(tag)) continue;
    tags.list(tag);
    gains.push_back("<" + std::string(tag) + ">");
  }
  if (!gains.empty()) {
    tags.diagnostics().warning(
        tags.where() + " " + joinedNames(gains) +
        ": read and ignored: bullet_sim holds the steering joints with position motors "
        "and turns the rear wheels with velocity motors, each as strong as its joint's "
        "URDF effort limit");
  }
  if (tags.has("steering_wheel_joint")) {
    tags.diagnostics().warning(tags.where() + " <steering_wheel_joint> [" +
                               tags.text("steering_wheel_joint") + "] is not turned by bullet_sim: ignored");
  }
  for (const char* tag : {"publish_wheel_tf", "publish_distance"}) {
    if (tags.flag(tag)) {
      tags.diagnostics().warning(tags.where() + " <" + tag + "> is not published by bullet_sim: ignored");
    }
  }
}

/// The tags, with ROS 2's names; the URDF's figures come later (readGeometry).
void readAckermannTags(PluginTags& tags, AckermannConfig& config) {
  // ROS 2's names first, and the ROS 1 names our other drives use.
  readDriveHead(tags,
                {{"command_topic", "commandTopic"},
                 {"odometry_topic", "odometryTopic"},
                 {"odometry_frame", "odometryFrame"},
                 {"robot_base_frame", "robotBaseFrame"}},
                config);

  config.front_left_joint = tags.text("front_left_joint");
  config.front_right_joint = tags.text("front_right_joint");
  config.rear_left_joint = tags.text("rear_left_joint");
  config.rear_right_joint = tags.text("rear_right_joint");
  config.left_steering_joint = tags.text("left_steering_joint");
  config.right_steering_joint = tags.text("right_steering_joint");

  config.max_steer = tags.positive("max_steer");
  if (config.max_steer >= M_PI / 2) {
    std::ostringstream message;
    message << tags.where() << " <max_steer> must be below pi/2 rad (a wheel across the car), not "
            << config.max_steer;
    tags.diagnostics().error(message.str());
    config.max_steer = tableDefaultNumber(tags, "max_steer");
  }
  config.max_speed = tags.positive("max_speed");
  config.publish_odometry = tags.flag("publish_odom");
  config.publish_odom_tf = tags.flag("publish_odom_tf");
  config.wheel_base = optionalPositive(tags, "wheel_base");
  config.track_width = optionalPositive(tags, "track_width");
  config.wheel_radius = optionalPositive(tags, "wheel_radius");
  readPlanarCovariance(tags, config);
  warnOfRos2Extras(tags);
}

/// Checks the joints the drive moves and reads their figures from the URDF at the zero pose.
class GeometryReader {
 public:
  GeometryReader(const ModelSpec& model, Diagnostics& diagnostics, const std::string& where,
                 AckermannConfig& config)
      : model_(model),
        diagnostics_(diagnostics),
        where_(where),
        config_(config),
        poses_(linkPosesAtZero(model_)),
        base_inverse_(poses_.at(config.base_link).inverse()) {}

  void read() {
    const JointSpec* left_hinge = steering("left_steering_joint", config_.left_steering_joint,
                                           config_.left_steering, config_.left_limits);
    const JointSpec* right_hinge = steering("right_steering_joint", config_.right_steering_joint,
                                            config_.right_steering, config_.right_limits);
    const JointSpec* rear_left = wheel("rear_left_joint", config_.rear_left_joint, config_.rear_left);
    const JointSpec* rear_right = wheel("rear_right_joint", config_.rear_right_joint, config_.rear_right);
    // The plugin lets the front wheels roll freely: they only have to exist and turn.
    const JointSpec* front_left = movingJoint("front_left_joint", config_.front_left_joint);
    const JointSpec* front_right = movingJoint("front_right_joint", config_.front_right_joint);
    if (!left_hinge || !right_hinge || !rear_left || !rear_right) return;
    measure(*left_hinge, *right_hinge, *rear_left, *rear_right);
    if (front_left && front_right) measureFront(*front_left, *front_right);
    checkFigures();
  }

 private:
  /// The joint a tag names, or nullptr once its problem is reported.
  const JointSpec* movingJoint(const std::string& tag, const std::string& joint_name) {
    const JointSpec* joint = model_.joint(joint_name);
    if (!joint) {
      diagnostics_.error(where_ + " <" + tag + "> [" + joint_name + "] is not a joint" +
                         didYouMean(joint_name, model_.jointNames()));
    } else if (!joint->moves()) {
      diagnostics_.error(where_ + " <" + tag + "> [" + joint_name + "] is a fixed joint: it must move");
      return nullptr;
    }
    return joint;
  }

  /// Where a joint is in the base frame: its child link's frame, through which the joint axis passes.
  Eigen::Isometry3d inBase(const JointSpec& joint) const { return base_inverse_ * poses_.at(joint.child); }

  const JointSpec* steering(const std::string& tag, const std::string& joint_name, AckermannJoint& out,
                            std::array<double, 2>& limits) {
    const JointSpec* joint = movingJoint(tag, joint_name);
    if (!joint) return nullptr;
    const Eigen::Vector3d axis = inBase(*joint).linear() * joint->axis;
    if (std::abs(axis.z()) < kMinVerticalAxis) {
      diagnostics_.error(where_ + " <" + tag + "> [" + joint_name + "] turns about " + vectorText(axis) +
                         " in [" + config_.base_link + "]: a steering joint turns about the vertical");
    }
    if (joint->effort <= 0) {
      diagnostics_.error(
          where_ + " <" + tag + "> [" + joint_name +
          "] has no effort limit, so nothing can steer it: set <limit effort=...> in the URDF");
    }
    out = {joint_name, axis.z() >= 0 ? 1.0 : -1.0, joint->effort};
    // The joint's limits as steering angles (positive = left), within max_steer.
    const double lower = out.sign > 0 ? joint->lower : -joint->upper;
    const double upper = out.sign > 0 ? joint->upper : -joint->lower;
    limits = {std::max(-config_.max_steer, lower), std::min(config_.max_steer, upper)};
    return joint;
  }

  const JointSpec* wheel(const std::string& tag, const std::string& joint_name, AckermannJoint& out) {
    const JointSpec* joint = movingJoint(tag, joint_name);
    if (!joint) return nullptr;
    out = {joint_name, wheelRollSign(poses_, config_.base_link, *joint), joint->effort};
    if (out.sign < 0) {
      diagnostics_.warning(where_ + " joint [" + joint_name + "] turns about " + vectorText(joint->axis) +
                           ", against the other wheels: it is driven with the opposite sign so the car rolls "
                           "forward");
    }
    if (joint->effort <= 0) {
      diagnostics_.error(
          where_ + " <" + tag + "> [" + joint_name +
          "] has no effort limit, so nothing can drive it: set <limit effort=...> in the URDF");
    }
    return joint;
  }

  void measure(const JointSpec& left_hinge, const JointSpec& right_hinge, const JointSpec& rear_left,
               const JointSpec& rear_right) {
    AckermannGeometry& geometry = config_.geometry;
    const Eigen::Vector3d left_kingpin = inBase(left_hinge).translation();
    const Eigen::Vector3d right_kingpin = inBase(right_hinge).translation();
    const Eigen::Vector3d left_rear = inBase(rear_left).translation();
    const Eigen::Vector3d right_rear = inBase(rear_right).translation();
    geometry.steering_track = left_kingpin.y() - right_kingpin.y();
    geometry.rear_track = left_rear.y() - right_rear.y();
    geometry.wheelbase = (left_kingpin.x() + right_kingpin.x()) / 2 - (left_rear.x() + right_rear.x()) / 2;
    if (geometry.steering_track <= 0 || geometry.rear_track <= 0) {
      diagnostics_.error(where_ + " the left joints must be to the left of the right ones in [" +
                         config_.base_link + "]: are <left_steering_joint>/<right_steering_joint> or " +
                         "<rear_left_joint>/<rear_right_joint> swapped?");
    }
    if (geometry.wheelbase <= 0) {
      diagnostics_.error(where_ + " the steering joints must be ahead of the rear wheels in [" +
                         config_.base_link + "]");
    }
    for (const JointSpec* joint : {&rear_left, &rear_right}) {
      const LinkSpec* link = model_.link(joint->child);
      const Shape* shape = link->collisions.empty() ? nullptr : &link->collisions.front().shape;
      if (!shape || (shape->type != Shape::Type::kCylinder && shape->type != Shape::Type::kSphere)) {
        diagnostics_.error(where_ + " rear wheel [" + link->name +
                           "] needs a cylinder or sphere collision: its radius is the wheel radius");
        continue;
      }
      geometry.wheel_radius = std::max(geometry.wheel_radius, shape->radius);
    }
  }

  /// The front wheels' roll signs and their distance apart, for those who drive them
  /// (ackermannJointCommands).
  void measureFront(const JointSpec& front_left, const JointSpec& front_right) {
    config_.front_left = {front_left.name, wheelRollSign(poses_, config_.base_link, front_left),
                          front_left.effort};
    config_.front_right = {front_right.name, wheelRollSign(poses_, config_.base_link, front_right),
                           front_right.effort};
    config_.geometry.front_track =
        inBase(front_left).translation().y() - inBase(front_right).translation().y();
  }

  void checkFigures() {
    const auto check = [&](const std::optional<double>& figure, const char* tag, double urdf,
                           const std::string& what) {
      if (!figure || std::abs(*figure - urdf) <= kGeometryTolerance) return;
      std::ostringstream message;
      message << where_ << " <" << tag << "> " << *figure << " m disagrees with the URDF, where " << what
              << " is " << urdf << " m: the URDF's figure is used";
      diagnostics_.warning(message.str());
    };
    const AckermannGeometry& geometry = config_.geometry;
    check(config_.wheel_base, "wheel_base", geometry.wheelbase, "the rear axle to the steering joints' line");
    check(config_.track_width, "track_width", geometry.rear_track,
          "[" + config_.rear_left_joint + "] to [" + config_.rear_right_joint + "]");
    check(config_.wheel_radius, "wheel_radius", geometry.wheel_radius, "the rear wheels' collision radius");
  }

  const ModelSpec& model_;
  Diagnostics& diagnostics_;
  const std::string& where_;
  AckermannConfig& config_;
  const std::map<std::string, Eigen::Isometry3d> poses_;
  const Eigen::Isometry3d base_inverse_;
};

}  // namespace

void parseAckermann(const DeclarationSource& source, AckermannConfig& config) {
  readAckermannTags(source.tags, config);
  readAckermannGeometry(source.model, source.tags.where(), config, source.diagnostics);
}

void readAckermannGeometry(const ModelSpec& model, const std::string& where, AckermannConfig& config,
                           Diagnostics& diagnostics) {
  config.base_link =
      frameLink(model, where, "robot_base_frame", config.robot_base_frame, model.root, diagnostics);
  GeometryReader(model, diagnostics, where, config).read();
}

double ackermannCurvatureLimit(const AckermannConfig& config, double side) {
  // A wheel at lateral offset y reaches angle a at curvature k = tan(a) / (L + y tan(a)). The wheel on the
  // inside of the turn always reaches its limit at a finite curvature (max_steer < pi/2); the outside one
  // may never.
  double limit = INFINITY;
  const AckermannGeometry& geometry = config.geometry;
  const double half = geometry.steering_track / 2;
  for (const auto& [y, limits] :
       {std::pair{half, config.left_limits}, std::pair{-half, config.right_limits}}) {
    const double tangent = std::tan(side > 0 ? limits[1] : limits[0]);
    const double denominator = geometry.wheelbase + y * tangent;
    if (denominator > 0) limit = std::min(limit, std::abs(tangent / denominator));
  }
  return side * limit;
}

AckermannJointCommands ackermannJointCommands(const AckermannConfig& config, double linear, double angular) {
  const AckermannGeometry& geometry = config.geometry;
  linear = std::clamp(linear, -config.max_speed, config.max_speed);
  // At v = 0 a turn cannot be driven: the wheels steer as far as they go towards the side of w.
  const double wanted = linear != 0 ? angular / linear : angular > 0 ? INFINITY : angular < 0 ? -INFINITY : 0;
  AckermannJointCommands commands;
  const double k =
      std::clamp(wanted, ackermannCurvatureLimit(config, -1), ackermannCurvatureLimit(config, 1));
  commands.curvature = k;
  const SteeringAngles angles = ackermannAngles(geometry.wheelbase, geometry.steering_track, k);
  commands.left_steering = config.left_steering.sign * angles.left;
  commands.right_steering = config.right_steering.sign * angles.right;
  // Each wheel rolls at the speed of its own distance from the turn centre (0, 1 / k): a rear wheel at
  // lateral offset y at v (1 - k y), a front one, L ahead, at v hypot(L k, 1 - k y).
  const auto spin = [&](const AckermannJoint& wheel, double rim_speed) {
    return wheel.sign * rim_speed / geometry.wheel_radius;
  };
  commands.rear_left = spin(config.rear_left, linear * (1 - k * geometry.rear_track / 2));
  commands.rear_right = spin(config.rear_right, linear * (1 + k * geometry.rear_track / 2));
  const double front_half = geometry.front_track / 2, lead = geometry.wheelbase * k;
  commands.front_left = spin(config.front_left, linear * std::hypot(lead, 1 - k * front_half));
  commands.front_right = spin(config.front_right, linear * std::hypot(lead, 1 + k * front_half));
  return commands;
}

SteeringAngles ackermannAngles(double wheelbase, double steering_track, double curvature) {
  // The axle line of a wheel at lateral offset y must pass through the turn centre (0, 1 / k) on the rear
  // axle line: tan = L / (1 / k - y) = L k / (1 - k y). atan2 keeps the sign for k < 0.
  const double half = steering_track / 2;
  return {std::atan2(wheelbase * curvature, 1 - curvature * half),
          std::atan2(wheelbase * curvature, 1 + curvature * half)};
}

AckermannDrive::AckermannDrive(const PluginDeclaration& declaration, const AckermannConfig& config,
                               const PluginSetup& setup)
    : DrivePlugin(declaration, config, setup),
      config_(config),
      left_steering_(setup.body.jointIndex(config.left_steering.name)),
      right_steering_(setup.body.jointIndex(config.right_steering.name)),
      rear_left_(setup.body.jointIndex(config.rear_left.name)),
      rear_right_(setup.body.jointIndex(config.rear_right.name)) {}

void AckermannDrive::applyCommands(const StepTime& time, RobotBody& body) {
  updated_this_step_ = timer().due(time);
  if (!updated_this_step_) return;
  const AckermannJointCommands commands =
      ackermannJointCommands(config_, command().linear(time), command().angular(time));
  curvature_ = commands.curvature;
  body.setJointPosition(left_steering_, commands.left_steering, config_.left_steering.effort);
  body.setJointPosition(right_steering_, commands.right_steering, config_.right_steering.effort);
  body.setJointVelocity(rear_left_, commands.rear_left, config_.rear_left.effort);
  body.setJointVelocity(rear_right_, commands.rear_right, config_.rear_right.effort);
}

void AckermannDrive::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!updated_this_step_) return;
  // The base's pose in the world, i.e. ground truth, as ROS 2's plugin reports it.
  fillGroundTruth(body, time.sim_time);
  publishOdometry();
}

void AckermannDrive::onReset() {
  DrivePlugin::onReset();
  curvature_ = 0;
}

// ROS 2's gazebo_plugins' Ackermann drive (Gazebo classic on ROS 1 has none).
BULLET_SIM_PLUGIN_FOLDER(ackermann_drive) {
  PluginType type =
      pluginType<AckermannDrive>("libgazebo_ros_ackermann_drive.so", parseAckermann, ackermannTags());
  type.rate = {RateRule::From::kTags, {"update_rate", "updateRate"}, 100};
  type.driven = [](const PluginDeclaration& declaration) {
    const AckermannConfig& config = *declaration.configAs<AckermannConfig>();
    DrivenJoints joints;
    joints.drive = true;  // each wheel's sign comes from its axis
    joints.traction = Traction{{config.rear_left_joint, config.rear_right_joint}, config.rear_left.effort,
                               config.geometry.wheel_radius, 0, config.max_speed};
    return joints;
  };
  type.wheel_model = [](const PluginDeclaration& declaration, const WheelModelQuery&) {
    return driveWheelModel(declaration);
  };
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
