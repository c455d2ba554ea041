#include "plugins/wheeled_drive/wheeled_drive.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "bullet_sim/model/model_geometry.h"

namespace bullet_sim {

namespace {

constexpr double kGeometryTolerance = 0.005;  // [m] plugin figures vs URDF geometry before we say so

/// The rows both drives share, in the order their tables list them: the topics, frames and rate first.
std::vector<TagRow> headRows() {
  return {
      {"commandTopic", TagType::kTopic, "cmd_vel", "",
       "the geometry_msgs/Twist it follows: linear.x [m/s] and angular.z [rad/s]", ""},
      {"odometryTopic", TagType::kTopic, "odom", "", "the topic of its nav_msgs/Odometry", ""},
      {"odometryFrame", TagType::kFrame, "odom", "",
       "the odometry's frame_id, and the parent frame of its tf", ""},
      {"robotBaseFrame", TagType::kFrame, "base_footprint", "",
       "the odometry's child_frame_id; the pose is the model's",
       "the pose is this link's; when it names no link, a warning, and the root link's pose"},
      {"updateRate", TagType::kRate, "100", "Hz",
       "how often the wheels get new speeds and the odometry is published; 0: every step", ""},
  };
}

/// The wheel figures both drives share.
std::vector<TagRow> wheelRows(const std::string& separation) {
  return {
      {"wheelSeparation", TagType::kNumber, separation, "m",
       "the distance between the left and right wheels; below 0: the robot turns the other way",
       "a warning when it is more than 5 mm off the distance between the wheels' joints; 0: the robot cannot "
       "turn, as in Gazebo, and encoder odometry, which Gazebo's divides by it (NaN), divides by the joints' "
       "distance; below 0: it turns the other way, as in Gazebo, with a warning, and encoder odometry "
       "divides by its absolute value"},
      {"wheelDiameter", TagType::kNumber, "0.15", "m",
       "the wheels' diameter; 0 or less: the wheels' speeds are divided by it (NaN or infinite)",
       "a warning when it is more than 5 mm off a wheel's collision cylinder or sphere; 0 or less: that "
       "collision's diameter, with a warning (an error when no wheel has one)"},
  };
}

/// A wheel joint's row.
TagRow jointRow(const std::string& tag, const std::string& fallback, const std::string& wheel) {
  return {tag, TagType::kText, fallback, "",
          "the " + wheel + " wheel's joint; the plugin does not load when the model has no such joint",
          "an error naming the nearest joint when it is missing or fixed; a wheel turning the other way "
          "(about -y) is driven with the opposite sign, with a warning"};
}

/// The tags that Gazebo's plugins share with older versions and that change nothing here.
std::vector<TagRow> ignoredRows(const std::string& debug_level) {
  return {
      {"rosDebugLevel", TagType::kIgnored, "", "", debug_level, ""},
      {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
  };
}

TagTable tableOf(const std::vector<std::vector<TagRow>>& parts) {
  TagTable table;
  for (const auto& part : parts) {
    for (const TagRow& row : part) table.add(row);
  }
  return table;
}

TagTable diffDriveTags() {
  return tableOf({
      headRows(),
      {jointRow("leftJoint", "left_joint", "left"), jointRow("rightJoint", "right_joint", "right")},
      wheelRows("0.34"),
      {
          {"wheelTorque", TagType::kPositive, "5", "N m", "the most torque each wheel's velocity motor gives",
           "above max_effort, that limit, with a warning; 0 or less: none, so the robot does not drive, as "
           "in Gazebo, with a warning"},
          {"wheelAcceleration", TagType::kNumber, "0", "m/s^2",
           "how fast the rims' speed may change towards the command; 0: at once; below 0: the commanded "
           "speed steps away from the command",
           "ramps the commanded rim speed from update to update; below 0: its absolute value, with a "
           "warning"},
          {"odometrySource", TagType::kText, "world", "",
           "world: the model's pose in the world; encoder: integrated from the wheels' speeds",
           "encoder integrates the angles the wheels turned; another value is read as world, with a warning"},
          {"publishTf", TagType::kFlag, "true", "",
           "false: no odometry, nor its tf; a warning when the tag is absent", "false: no odometry message"},
          {"publishOdomTF", TagType::kFlag, "true", "",
           "the odometry's tf (odometryFrame to robotBaseFrame), sent with each odometry",
           "sent even when publishTf is false"},
          {"publishWheelTF", TagType::kFlag, "false", "",
           "each wheel's link in its parent link's frame on /tf", ""},
          {"publishWheelJointState", TagType::kFlag, "false", "",
           "the wheels' positions on joint_states (sensor_msgs/JointState)",
           "their velocities and efforts too"},
          {"legacyMode", TagType::kFlag, "false", "",
           "not read on Noetic; Kinetic's and Melodic's swapped the wheels when true, their default",
           "read and ignored with a warning: REP 103 is followed"},
      },
      ignoredRows("the log level of the plugin's ROS node"),
      ownDriveTagRows(),
  });
}

TagTable skidSteerTags() {
  const auto covariance = [](const std::string& tag, const std::string& fallback, const std::string& of) {
    return TagRow{tag, TagType::kPositive, fallback, "", "the variance of " + of + " in the odometry's pose "
                  "and twist covariances", ""};
  };
  return tableOf({
      headRows(),
      {jointRow("leftFrontJoint", "left_front_joint", "left front"),
       jointRow("rightFrontJoint", "right_front_joint", "right front"),
       jointRow("leftRearJoint", "left_rear_joint", "left rear"),
       jointRow("rightRearJoint", "right_rear_joint", "right rear")},
      wheelRows("0.4"),
      {
          {"torque", TagType::kPositive, "5", "N m", "the most torque each wheel's velocity motor gives",
           "above max_effort, that limit, with a warning; 0 or less: none, so the robot does not drive, as "
           "in Gazebo, with a warning"},
          {"broadcastTF", TagType::kFlag, "false", "",
           "the odometry's tf (odometryFrame to robotBaseFrame), sent with each odometry", ""},
          covariance("covariance_x", "0.0001", "x [m^2]"),
          covariance("covariance_y", "0.0001", "y [m^2]"),
          covariance("covariance_yaw", "0.01", "the yaw [rad^2]"),
      },
      ignoredRows("not read"),
      ownDriveTagRows(),
  });
}

void readCommon(const DeclarationSource& source, DriveConfig& config) {
  PluginTags& tags = source.tags;
  readDriveHead(tags, DriveTagNames{}, config);
  config.wheel_separation = tags.number("wheelSeparation");  // 0 or less: checkWheels says what it means
  config.wheel_diameter = tags.number("wheelDiameter");  // not above 0: measureWheelDiameter
  for (const auto& [tag, value] : {std::pair{"wheelSeparation", &config.wheel_separation},
                                   std::pair{"wheelDiameter", &config.wheel_diameter}}) {
    if (auto problem = boundProblem(*value, source.limits.max_length, "max_length", "m"))
      source.diagnostics.error(tags.where() + " <" + tag + "> " + *problem);
  }
}

/// A wheel's velocity motor's torque limit [N m], read from `tag`: 0 or less, the robot does not drive.
double wheelTorque(const DeclarationSource& source, const std::string& tag) {
  return source.tags.motorLimit(tag, tableDefaultNumber(source.tags, tag), source.limits.max_effort,
                                "max_effort", "N m");
}

/// A wheel named twice, on both sides or on one, would be driven twice: an error.
void checkWheelsDistinct(const DeclarationSource& source, const DriveConfig& config) {
  std::vector<std::string> seen;
  for (const auto* side : {&config.left_joints, &config.right_joints}) {
    for (const auto& joint : *side) {
      if (std::find(seen.begin(), seen.end(), joint) != seen.end()) {
        source.diagnostics.error(source.tags.where() + " names joint [" + joint +
                                 "] for two wheels: each wheel of a drive is a joint of its own");
      }
      seen.push_back(joint);
    }
  }
}

/// The diameter [m] of the collision cylinder or sphere of joint `name`'s child link, when it has one first.
std::optional<double> collisionDiameter(const ModelSpec& model, const std::string& name) {
  const JointSpec* joint = model.joint(name);
  const LinkSpec* link = joint ? model.link(joint->child) : nullptr;
  if (!link || link->collisions.empty()) return std::nullopt;
  const Shape& shape = link->collisions.front().shape;
  if (shape.type != Shape::Type::kCylinder && shape.type != Shape::Type::kSphere) return std::nullopt;
  return 2 * shape.radius;
}

/// A wheelDiameter not above 0, which Gazebo divides the wheels' speeds by, becomes the first wheel's
/// collision diameter, with a warning; an error when no wheel has a cylinder or sphere to measure.
void measureWheelDiameter(const DeclarationSource& source, DriveConfig& config) {
  if (config.wheel_diameter > 0) return;
  std::ostringstream message;
  message << source.tags.where() << " <wheelDiameter> " << config.wheel_diameter << " m is not above 0";
  for (const auto& name : driveWheels(config)) {
    const std::optional<double> diameter = collisionDiameter(source.model, name);
    if (!diameter) continue;
    config.wheel_diameter = *diameter;
    message << ": " << *diameter << " m, the collision diameter of joint [" << name
            << "]'s wheel, is used (Gazebo would set its wheels' speeds to the command divided by it)";
    source.diagnostics.warning(message.str());
    return;
  }
  message << ", and no wheel has a collision cylinder or sphere to measure it by: give the wheels' diameter";
  source.diagnostics.error(message.str());
}

/// Checks one side's wheels against the model: each must be a moving joint; a reversed one and a collision
/// of another diameter are said. Returns each wheel's roll sign and its offset across the base [m].
std::vector<double> checkSide(const DeclarationSource& source, const DriveConfig& config,
                              const std::vector<std::string>& joints, std::vector<double>& lateral) {
  const ModelSpec& model = source.model;
  Diagnostics& diagnostics = source.diagnostics;
  const std::string& where = source.tags.where();
  const auto poses = linkPosesAtZero(model);
  const Eigen::Isometry3d base = poses.at(config.base_link);
  std::vector<double> signs;
  for (const auto& name : joints) {
    const JointSpec* joint = model.joint(name);
    if (!joint || !joint->moves()) {
      diagnostics.error(where + " names joint [" + name + "], which " +
                        (joint ? "is fixed: wheels need continuous joints" : "does not exist") +
                        (joint ? "" : didYouMean(name, model.jointNames())));
      signs.push_back(1);
      continue;
    }
    signs.push_back(wheelRollSign(poses, config.base_link, *joint));
    if (signs.back() < 0) {
      diagnostics.warning(where + " joint [" + name + "] turns about " + vectorText(joint->axis) +
                          ", against the other side: it is driven with the opposite sign so the robot rolls "
                          "forward (Gazebo would spin it in place)");
    }
    const auto diameter = collisionDiameter(model, name);
    if (diameter && config.wheel_diameter > 0 &&
        std::abs(*diameter - config.wheel_diameter) > kGeometryTolerance) {
      std::ostringstream message;
      message << where << " <wheelDiameter> " << config.wheel_diameter << " m disagrees with link ["
              << joint->child << "], whose collision is " << *diameter << " m across";
      diagnostics.warning(message.str());
    }
    lateral.push_back((base.inverse() * poses.at(joint->child)).translation().y());
  }
  return signs;
}

/// With encoder odometry and a wheelSeparation of 0, which Gazebo's odometry divides by (NaN), ours divides
/// by the joints' `separation` instead: what the warning says of it.
std::string useJointSeparation(DriveConfig& config, double separation) {
  if (!config.odometry_from_encoders || config.encoder_separation != 0) return "";
  config.encoder_separation = separation;
  std::ostringstream text;
  text << "; the encoder odometry divides by their " << separation << " m instead (Gazebo's would be NaN)";
  return text.str();
}

/// A wheelSeparation below 0 turns the robot the other way, in Gazebo too (its wheels get
/// v -/+ w * separation / 2): a warning says so. Encoder odometry divides by its absolute value.
void warnNegativeSeparation(const DeclarationSource& source, const DriveConfig& config) {
  if (!(config.wheel_separation < 0)) return;
  std::ostringstream message;
  message << source.tags.where() << " <wheelSeparation> " << config.wheel_separation
          << " m is below 0: the robot turns the other way from its commands, as in Gazebo, whose wheels get "
             "v -/+ w * separation / 2";
  if (config.odometry_from_encoders) {
    message << "; the encoder odometry divides by " << config.encoder_separation
            << " m, so it follows the robot (Gazebo's turns the other way from it)";
  }
  source.diagnostics.warning(message.str());
}

/// Checks the wheels against the model (see checkSide) and wheelSeparation against their joints.
void checkWheels(const DeclarationSource& source, DriveConfig& config) {
  checkWheelsDistinct(source, config);
  config.base_link = frameLink(source, "robotBaseFrame", config.robot_base_frame, source.model.root);
  std::vector<double> left_y, right_y;
  measureWheelDiameter(source, config);
  config.left_signs = checkSide(source, config, config.left_joints, left_y);
  config.right_signs = checkSide(source, config, config.right_joints, right_y);
  config.encoder_separation = std::abs(config.wheel_separation);
  warnNegativeSeparation(source, config);
  for (size_t i = 0; i < std::min(left_y.size(), right_y.size()); ++i) {
    const double separation = left_y[i] - right_y[i];
    if (std::abs(separation - config.encoder_separation) > kGeometryTolerance) {
      std::ostringstream message;
      message << source.tags.where() << " <wheelSeparation> " << config.wheel_separation
              << " m disagrees with the joints [" << config.left_joints[i] << "] and ["
              << config.right_joints[i] << "], which are " << separation << " m apart";
      if (config.wheel_separation == 0)
        message << ": the robot cannot turn, as in Gazebo" << useJointSeparation(config, separation);
      source.diagnostics.warning(message.str());
    }
  }
  if (config.odometry_from_encoders && config.encoder_separation == 0) {
    source.diagnostics.error(source.tags.where() + " <odometrySource> encoder divides the wheels' travel by "
                             "<wheelSeparation>, which is 0, as is their joints' separation: give the "
                             "separation, or use world odometry");
  }
}

/// wheelAcceleration [m/s^2]. Gazebo's ramp steps by it towards the command, so one below 0 steps away
/// from it: its absolute value is used, with a warning.
double wheelAcceleration(PluginTags& tags) {
  const double value = tags.number("wheelAcceleration");
  if (!(value < 0)) return value;
  std::ostringstream message;
  message << tags.where() << " <wheelAcceleration> " << value << " m/s^2 is below 0: read as " << -value
          << " m/s^2 (Gazebo's ramp would step the wheels' speeds away from the command)";
  tags.diagnostics().warning(message.str());
  return -value;
}

}  // namespace

void parseDiffDrive(const DeclarationSource& source, DriveConfig& config) {
  PluginTags& tags = source.tags;
  readCommon(source, config);
  config.left_joints = {tags.text("leftJoint")};
  config.right_joints = {tags.text("rightJoint")};
  config.torque = wheelTorque(source, "wheelTorque");
  config.acceleration = wheelAcceleration(tags);
  const std::string odometry_source = tags.text("odometrySource");
  if (odometry_source == "encoder") {
    config.odometry_from_encoders = true;  // with a wheelSeparation of 0: checkWheels
  } else if (odometry_source != "world") {
    tags.diagnostics().warning(tags.where() + " <odometrySource> must be world or encoder, not [" +
                               odometry_source + "]: world is used, as Gazebo does");
  }
  config.publish_odometry = tags.flag("publishTf");
  config.publish_odom_tf = tags.flag("publishOdomTF");
  config.publish_wheel_tf = tags.flag("publishWheelTF");
  config.publish_wheel_joint_state = tags.flag("publishWheelJointState");
  if (tags.has("legacyMode")) {
    tags.flag("legacyMode");
    tags.diagnostics().warning(
        tags.where() +
        " <legacyMode> is a Kinetic tag (it swapped the wheels): ignored; REP 103 is followed");
  }
  config.pose_covariance = config.twist_covariance = planarCovariance(1e-5, 1e-5, 1e-3);
  checkWheels(source, config);
}

void parseSkidSteer(const DeclarationSource& source, DriveConfig& config) {
  PluginTags& tags = source.tags;
  readCommon(source, config);
  config.left_joints = {tags.text("leftFrontJoint"), tags.text("leftRearJoint")};
  config.right_joints = {tags.text("rightFrontJoint"), tags.text("rightRearJoint")};
  config.torque = wheelTorque(source, "torque");
  config.publish_odometry = true;  // Gazebo's skid steer always publishes it
  config.publish_odom_tf = tags.flag("broadcastTF");
  readPlanarCovariance(tags, config);
  checkWheels(source, config);
}

WheeledDrive::WheeledDrive(const PluginDeclaration& declaration, const DriveConfig& config,
                           const PluginSetup& setup)
    : DrivePlugin(declaration, config, setup), config_(config) {
  const auto addWheels = [&](const std::vector<std::string>& names, const std::vector<double>& signs,
                             std::vector<Wheel>& wheels) {
    for (size_t i = 0; i < names.size(); ++i) {
      const JointSpec& joint = *setup.body.spec().joint(names[i]);
      wheels.push_back({setup.body.jointIndex(names[i]), signs[i], 0, 0, joint.parent, joint.child});
      wheel_states_.next().names.push_back(names[i]);
    }
  };
  addWheels(config_.left_joints, config_.left_signs, left_);
  addWheels(config_.right_joints, config_.right_signs, right_);
  if (config_.publish_wheel_joint_state) addOutput("joint_states", wheel_states_);
  if (config_.publish_wheel_tf) addOutput("", wheel_tf_);
}

void WheeledDrive::applyCommands(const StepTime& time, RobotBody& body) {
  updated_this_step_ = timer().due(time);
  if (!updated_this_step_) return;
  const double elapsed = time.sim_time - last_update_;
  last_update_ = time.sim_time;

  const double linear = command().linear(time);
  const double angular = command().angular(time);
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
  const double turn = (right - left) / config_.encoder_separation;
  encoder_pose_.x() += distance * std::cos(encoder_pose_.z() + turn / 2);
  encoder_pose_.y() += distance * std::sin(encoder_pose_.z() + turn / 2);
  encoder_pose_.z() += turn;
  return {distance, turn};
}

void WheeledDrive::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!updated_this_step_) return;
  if (config_.odometry_from_encoders) {
    Odometry& odometry = nextOdometry();
    const double elapsed = time.sim_time - odometry.stamp;
    odometry.stamp = time.sim_time;
    const Eigen::Vector2d moved = integrateEncoders(body);  // distance [m], turn [rad]
    odometry.pose = Eigen::Translation3d(encoder_pose_.x(), encoder_pose_.y(), 0) *
                    Eigen::AngleAxisd(encoder_pose_.z(), Eigen::Vector3d::UnitZ());
    odometry.linear_velocity = Eigen::Vector3d(moved.x() / elapsed, 0, 0);
    odometry.angular_velocity = Eigen::Vector3d(0, 0, moved.y() / elapsed);
  } else {
    fillGroundTruth(body, time.sim_time);
  }
  publishOdometry();
  publishWheels(time, body);
}

void WheeledDrive::publishWheels(const StepTime& time, const RobotBody& body) {
  if (config_.publish_wheel_joint_state) {
    JointStateSample& states = wheel_states_.next();
    states.stamp = time.sim_time;
    states.positions.clear();
    states.velocities.clear();
    states.efforts.clear();
    for (const auto* wheels : {&left_, &right_}) {
      for (const auto& wheel : *wheels) {
        states.positions.push_back(body.jointPosition(wheel.joint));
        states.velocities.push_back(body.jointVelocity(wheel.joint));
        states.efforts.push_back(body.jointEffort(wheel.joint));
      }
    }
    wheel_states_.publish();
  }
  if (config_.publish_wheel_tf) {
    TransformSample& tf = wheel_tf_.next();
    tf.stamp = time.sim_time;
    tf.frames.clear();
    for (const auto* wheels : {&left_, &right_}) {
      for (const auto& wheel : *wheels) {
        tf.frames.push_back({wheel.parent_link, wheel.link,
                             body.linkPose(wheel.parent_link).inverse() * body.linkPose(wheel.link)});
      }
    }
    wheel_tf_.publish();
  }
}

void WheeledDrive::onReset() {
  DrivePlugin::onReset();
  last_update_ = 0;
  encoder_pose_.setZero();
  for (auto* wheels : {&left_, &right_}) {
    for (auto& wheel : *wheels) wheel.rim_speed = wheel.last_position = 0;
  }
}

std::vector<std::string> driveWheels(const DriveConfig& config) {
  std::vector<std::string> wheels = config.left_joints;
  wheels.insert(wheels.end(), config.right_joints.begin(), config.right_joints.end());
  return wheels;
}

BULLET_SIM_PLUGIN_FOLDER(wheeled_drive) {
  const auto driven = [](const PluginDeclaration& declaration) {
    const DriveConfig& config = *declaration.configAs<DriveConfig>();
    DrivenJoints joints{true, config.left_joints, config.right_joints, config.robot_base_frame};
    joints.traction =
        Traction{driveWheels(config), config.torque, config.wheel_diameter / 2, config.acceleration};
    return joints;
  };
  using Parser = void (*)(const DeclarationSource&, DriveConfig&);
  const auto add = [&](const char* filename, Parser parse, TagTable tags) {
    PluginType type = pluginType<WheeledDrive>(filename, parse, std::move(tags));
    type.rate = {RateRule::From::kTags, {"updateRate"}, 100};
    type.driven = driven;
    type.check = checkWheeledDrive;
    type.wheel_model = [](const PluginDeclaration& declaration, const WheelModelQuery&) {
      return driveWheelModel(declaration);
    };
    registrar.add(std::move(type));
  };
  add("libgazebo_ros_diff_drive.so", parseDiffDrive, diffDriveTags());
  add("libgazebo_ros_skid_steer_drive.so", parseSkidSteer, skidSteerTags());
}

}  // namespace bullet_sim
