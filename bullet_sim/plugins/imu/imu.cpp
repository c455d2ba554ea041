#include "plugins/imu/imu.h"

#include "bullet_sim/plugins/registry.h"

namespace bullet_sim {

void parseImuSensor(const DeclarationSource& source, ImuConfig& config) {
  PluginTags& tags = source.tags;
  config.topic = tags.text("topicName", config.topic);
  config.frame = tags.frame("frameName", config.link, /*gazebo_drops_slash=*/false);
  config.noise_stddev = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
  tags.accept(
      {"alwaysOn", "updateRate", "bodyName", "xyzOffset", "rpyOffset", "initialOrientationAsReference"});
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
  config.topic = tags.text("topicName", config.topic);
  config.noise_stddev = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
  tags.accept({"serviceName", "alwaysOn", "xyzOffsets", "rpyOffsets"});
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
  PluginType model_plugin = pluginType<Imu>("libgazebo_ros_imu.so", parseImuPlugin, {});
  model_plugin.rate = {RateRule::From::kTags, {"updateRate"}, 0};
  model_plugin.needs = kNeedGravity;
  model_plugin.tf_prefix = TfPrefixRule::kNone;
  registrar.add(std::move(model_plugin));
  PluginType sensor_plugin = pluginType<Imu>("libgazebo_ros_imu_sensor.so", parseImuSensor, {});
  sensor_plugin.sensor_types = {"imu"};
  sensor_plugin.rate = {RateRule::From::kTagsOverSensor, {"updateRateHZ"}, 0};
  sensor_plugin.needs = kNeedGravity;
  sensor_plugin.tf_prefix = TfPrefixRule::kNone;
  registrar.add(std::move(sensor_plugin));
}

}  // namespace bullet_sim
