#include "plugins/imu/imu.h"

#include "bullet_sim/plugins/gazebo_plugin_rows.h"
#include "bullet_sim/plugins/registry.h"

namespace bullet_sim {

namespace {

const TagTable kImuSensorTags = {
    {"topicName", TagType::kTopic, "imu", "", "the topic of the readings; imu_data when absent",
     "imu when absent"},
    {"frameName", TagType::kFrame, "the sensor's link", "",
     "the messages' frame_id; required: the plugin does not load without it",
     "the sensor's link when absent; a name that is no link is a warning, and is still the frame_id"},
    {"updateRateHZ", TagType::kRate, "the sensor's", "Hz",
     "throttles the plugin below the sensor's <update_rate>; 1 Hz when absent",
     "the plugin's rate when given, else the sensor's <update_rate>"},
    {"gaussianNoise", TagType::kDeviation, "0", "",
     "the standard deviation of a zero-mean noise on every value, the orientation's included",
     "on the angular velocity [rad/s] and the linear acceleration [m/s^2] only: the orientation is exact"},
    {"rpyOffset", TagType::kIgnored, "", "rad", "turns the orientation reading by these roll, pitch and yaw",
     "not honoured"},
    {"xyzOffset", TagType::kIgnored, "", "m", "read, and without effect", ""},
    {"initialOrientationAsReference", TagType::kIgnored, "", "",
     "true: orientations relative to the first one (deprecated); false when absent",
     "orientations are in the world frame, as with false (REP 145)"},
    {"updateRate", TagType::kIgnored, "", "Hz", "not read (updateRateHZ is this plugin's)", ""},
    {"bodyName", TagType::kIgnored, "", "", "not read (the sensor's link is measured)", ""},
    {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
};

const TagTable kImuPluginTags = withUnreadTutorialTags({
    {"bodyName", TagType::kFrame, "", "", "the link measured; required: the plugin does not load without it",
     "an error when absent; a name that is no link is a warning, the root link is measured, and the name is "
     "still the frame_id"},
    {"frameName", TagType::kFrame, "bodyName", "", "the messages' frame_id", ""},
    {"topicName", TagType::kTopic, "imu", "", "the topic of the readings; /default_imu when absent",
     "imu when absent, relative to the namespace"},
    {"updateRate", TagType::kRate, "0", "Hz", "how often it publishes; 0: every step", ""},
    {"gaussianNoise", TagType::kDeviation, "0", "",
     "the standard deviation of a zero-mean noise on the angular velocity [rad/s] and the "
     "acceleration [m/s^2]",
     ""},
    {"serviceName", TagType::kIgnored, "", "",
     "a std_srvs/Empty service that does nothing; /default_imu when absent", "not served"},
});

}  // namespace

void parseImuSensor(const DeclarationSource& source, ImuConfig& config) {
  PluginTags& tags = source.tags;
  config.topic = tags.text("topicName");
  config.frame = tags.frame("frameName", config.link, /*gazebo_drops_slash=*/false);
  config.noise_stddev = tags.deviation("gaussianNoise");
  frameLink(source, "frameName", config.frame);
}

void parseImuPlugin(const DeclarationSource& source, ImuConfig& config) {
  PluginTags& tags = source.tags;
  const ModelSpec& model = source.model;
  if (!tags.has("bodyName"))
    source.diagnostics.error(tags.where() + " has no <bodyName>: name the link it sits on");
  const std::string body = tags.frame("bodyName", model.root, /*gazebo_drops_slash=*/false);
  config.link = frameLink(source, "bodyName", body, model.root);
  config.frame = tags.frame("frameName", body, /*gazebo_drops_slash=*/false);
  config.topic = tags.text("topicName");
  config.noise_stddev = tags.deviation("gaussianNoise");
  if (config.frame != body) frameLink(source, "frameName", config.frame);
}

Imu::Imu(const PluginDeclaration& declaration, const ImuConfig& config, const PluginSetup& setup)
    : Plugin(declaration, setup), config_(config), gravity_(setup.gravity) {
  ImuSample& sample = samples_.next();
  sample.frame_id = config_.frame;
  const Eigen::Vector3d variance = Eigen::Vector3d::Constant(config_.noise_stddev * config_.noise_stddev);
  sample.angular_velocity_variance = sample.linear_acceleration_variance = variance;
  addOutput(config_.topic, samples_);
}

void Imu::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer().due(time)) return;
  const Eigen::Isometry3d frame = body.linkPose(config_.link) * config_.pose;
  const Eigen::Matrix3d to_frame = frame.linear().transpose();
  const Eigen::Vector3d velocity = body.linkLinearVelocity(config_.link);
  const Eigen::Vector3d acceleration =
      last_time_ >= 0 ? Eigen::Vector3d((velocity - last_velocity_) / (time.sim_time - last_time_))
                      : Eigen::Vector3d::Zero();
  last_velocity_ = velocity;
  last_time_ = time.sim_time;

  ImuSample& sample = samples_.next();
  sample.stamp = time.sim_time;
  sample.orientation = Eigen::Quaterniond(frame.linear());
  sample.angular_velocity =
      to_frame * body.linkAngularVelocity(config_.link) + gaussian3(config_.noise_stddev);
  sample.linear_acceleration = to_frame * (acceleration - gravity_) + gaussian3(config_.noise_stddev);
  samples_.publish();
}

void Imu::onReset() {
  last_time_ = -1;
  last_velocity_.setZero();
}

BULLET_SIM_PLUGIN_FOLDER(imu) {
  PluginType model_plugin = pluginType<Imu>("libgazebo_ros_imu.so", parseImuPlugin, kImuPluginTags);
  model_plugin.rate = {RateRule::From::kTags, {"updateRate"}, 0};
  model_plugin.needs = kNeedGravity;
  model_plugin.tf_prefix = TfPrefixRule::kNone;
  registrar.add(std::move(model_plugin));
  PluginType sensor_plugin = pluginType<Imu>("libgazebo_ros_imu_sensor.so", parseImuSensor, kImuSensorTags);
  sensor_plugin.sensor_types = {"imu"};
  sensor_plugin.rate = {RateRule::From::kTagsOverSensor, {"updateRateHZ"}, 0};
  sensor_plugin.needs = kNeedGravity;
  sensor_plugin.tf_prefix = TfPrefixRule::kNone;
  registrar.add(std::move(sensor_plugin));
}

}  // namespace bullet_sim
