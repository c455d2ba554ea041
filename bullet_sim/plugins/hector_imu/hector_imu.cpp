#include "plugins/hector_imu/hector_imu.h"

#include "bullet_sim/plugins/registry.h"

#include <cmath>

namespace bullet_sim {

namespace {

TagTable hectorImuTags() {
  const std::vector<TagRow> own = {
      {"frameId", TagType::kFrame, "bodyName", "", "the messages' frame_id", ""},
      {"topicName", TagType::kTopic, "imu", "", "the topic of the readings", ""},
      {"biasTopicName", TagType::kTopic, "<topicName>/bias", "",
       "the topic of the current biases, as a sensor_msgs/Imu", ""},
      {"serviceName", TagType::kText, "<topicName>/calibrate", "",
       "a std_srvs/Empty service that zeroes the rate drift", ""},
      {"rpyOffset", TagType::kText, "0 0 0", "rad", "roll, pitch and yaw that turn the reading", ""},
      {"xyzOffset", TagType::kIgnored, "", "m", "read, and without effect", ""},
      {"gaussianNoise", TagType::kDeviation, "0", "",
       "gazebo_ros_imu's tag: when not 0, the accel and rate white noise on every axis", ""},
      {"headingDrift", TagType::kPositive, "yawDrift's", "rad",
       "not read (older hector's name of yawDrift, which Husky's description writes)",
       "read as yawDrift unless that is given, with a warning"},
      {"headingGaussianNoise", TagType::kDeviation, "yawGaussianNoise's", "rad",
       "not read (older hector's name of yawGaussianNoise)",
       "read as yawGaussianNoise unless that is given, with a warning"},
      {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
  };
  TagTable table;
  for (const auto& rows :
       {hectorBodyAndTimerRows("0"), own, sensorErrorRows("accel", /*vector=*/true, "m/s^2"),
        sensorErrorRows("rate", /*vector=*/true, "rad/s"), sensorErrorRows("yaw", /*vector=*/false, "rad")}) {
    for (const TagRow& row : rows) table.add(row);
  }
  return table;
}

/// Husky's headingDrift and headingGaussianNoise: hector's old names for the yaw model's tags.
void readHeadingTags(PluginTags& tags, SensorErrorConfig& yaw) {
  const char* const old_names[] = {"headingDrift", "headingGaussianNoise"};
  const char* const new_names[] = {"yawDrift", "yawGaussianNoise"};
  double* const values[] = {&yaw.drift.x(), &yaw.gaussian_noise.x()};
  for (int i = 0; i < 2; ++i) {
    if (!tags.has(old_names[i])) continue;
    const double value = i == 0 ? tags.positive(old_names[i], *values[i], /*allow_zero=*/true)
                                : tags.deviation(old_names[i], *values[i]);
    const std::string new_name = std::string("<") + new_names[i] + ">";
    const bool superseded = tags.has(new_names[i]);
    if (!superseded) *values[i] = value;
    const std::string outcome =
        superseded ? "ignored, since " + new_name + " is given" : "read as " + new_name;
    tags.diagnostics().warning(tags.where() + " <" + old_names[i] + "> is hector's old name of " + new_name +
                               ", which today's hector ignores: " + outcome);
  }
}

}  // namespace

void parseHectorImu(const DeclarationSource& source, HectorImuConfig& config) {
  PluginTags& tags = source.tags;
  std::string body;
  config.link = readHectorBody(source, &body);
  config.frame = tags.frame("frameId", body, /*gazebo_drops_slash=*/false);
  if (tags.has("frameId")) frameLink(source, "frameId", config.frame);
  config.topic = tags.text("topicName");
  config.bias_topic = tags.text("biasTopicName", config.topic.empty() ? "" : config.topic + "/bias");
  config.service = tags.text("serviceName", config.topic + "/calibrate");
  config.update_rate = readHectorUpdateRate(tags);
  config.accel = readSensorError(tags, "accel", /*vector=*/true);
  config.rate = readSensorError(tags, "rate", /*vector=*/true);
  config.yaw = readSensorError(tags, "yaw", /*vector=*/false);
  readHeadingTags(tags, config.yaw);
  if (const double noise = tags.deviation("gaussianNoise"); noise != 0)
    config.accel.gaussian_noise = config.rate.gaussian_noise = Eigen::Vector3d::Constant(noise);
  const Eigen::Vector3d rpy = readVector3(tags, "rpyOffset");
  config.rpy_offset = Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                      Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                      Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX());
  source.diagnostics.warning(tags.where() + " hector's [" + config.topic + "/set_accel_bias] and [" +
                             config.topic +
                             "/set_rate_bias] services and its dynamic_reconfigure servers need hector's own "
                             "types, which Debian lacks: left out");
}

HectorImu::HectorImu(const PluginDeclaration& declaration, const HectorImuConfig& config,
                     const PluginSetup& setup)
    : Plugin(declaration, setup),
      config_(config),
      gravity_(setup.gravity),
      accel_error_(config.accel),
      rate_error_(config.rate),
      yaw_error_(config.yaw) {
  ImuSample& sample = samples_.next();
  sample.frame_id = biases_.next().frame_id = config_.frame;
  sample.angular_velocity_variance = config_.rate.gaussian_noise.cwiseAbs2();
  sample.linear_acceleration_variance = config_.accel.gaussian_noise.cwiseAbs2();
  const double g2 = gravity_.squaredNorm();
  const Eigen::Vector3d accel_variance = config_.accel.gaussian_noise.cwiseAbs2();
  sample.orientation_variance = {g2 > 0 ? accel_variance.x() / g2 : -1, g2 > 0 ? accel_variance.y() / g2 : -1,
                                 config_.yaw.gaussian_noise.x() * config_.yaw.gaussian_noise.x()};
  if (!config_.topic.empty()) addOutput(config_.topic, samples_);
  if (!config_.bias_topic.empty()) addOutput(config_.bias_topic, biases_);
  if (!config_.service.empty()) {
    addService<EmptyRequest>(config_.service, [this](const EmptyRequest&) {
      calibrate();
      return std::string();
    });
  }
  onReset();
}

void HectorImu::calibrate() { rate_error_.setDrift(Eigen::Vector3d::Zero()); }

void HectorImu::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer().due(time)) return;
  const double dt = last_update_ >= 0 ? time.sim_time - last_update_ : 0.0;
  last_update_ = time.sim_time;
  const Eigen::Quaterniond link_rotation(body.linkPose(config_.link).linear());
  const Eigen::Quaterniond rotation = (config_.rpy_offset * link_rotation).normalized();
  // Before the first update there is no earlier velocity: the link reads as unaccelerated (hector reads 0).
  const Eigen::Vector3d velocity = body.linkLinearVelocity(config_.link);
  const Eigen::Vector3d acceleration = dt > 0 ? Eigen::Vector3d((velocity - last_velocity_) / dt)
                                              : Eigen::Vector3d::Zero();
  last_velocity_ = velocity;
  const Eigen::Vector3d rate =
      config_.rpy_offset.inverse() * (link_rotation.inverse() * body.linkAngularVelocity(config_.link));

  ImuSample& sample = samples_.next();
  sample.stamp = time.sim_time;
  const Eigen::Vector3d specific_force = rotation.inverse() * (acceleration - gravity_);
  sample.linear_acceleration = accel_error_.apply(specific_force, dt, noise());
  sample.angular_velocity = rate_error_.apply(rate, dt, noise());
  yaw_error_.apply(Eigen::Vector3d::Zero(), dt, noise());

  // hector's pseudo-AHRS: the yaw bias turns the orientation about z, the accel bias tilts it.
  const double g = gravity_.norm();
  const Eigen::Vector3d accel_drift = link_rotation * accel_error_.bias();
  const double yaw = yaw_error_.bias().x();
  Eigen::Quaterniond error = Eigen::Quaterniond(std::cos(yaw / 2), 0, 0, std::sin(yaw / 2));
  if (g > 0) error = error * Eigen::Quaterniond(1, 0.5 * accel_drift.y() / g, -0.5 * accel_drift.x() / g, 0);
  error.normalize();
  sample.orientation = (error * rotation).normalized();
  samples_.publish();
  publishBias(error);
}

void HectorImu::publishBias(const Eigen::Quaterniond& orientation_error) {
  ImuSample& bias = biases_.next();
  bias.stamp = samples_.latest().stamp;
  bias.orientation = orientation_error;
  bias.angular_velocity = rate_error_.bias();
  bias.linear_acceleration = accel_error_.bias();
  biases_.publish();
}

void HectorImu::onReset() {
  last_update_ = -1;
  last_velocity_.setZero();
  accel_error_.reset(noise());
  rate_error_.reset(noise());
  yaw_error_.reset(noise());
}

BULLET_SIM_PLUGIN_FOLDER(hector_imu) {
  PluginType type = pluginType<HectorImu>("libhector_gazebo_ros_imu.so", parseHectorImu, hectorImuTags());
  type.needs = kNeedGravity;
  type.tf_prefix = TfPrefixRule::kNone;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
