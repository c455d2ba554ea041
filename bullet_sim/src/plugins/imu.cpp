#include "bullet_sim/plugins/imu.h"

namespace bullet_sim {

namespace {

void checkFrame(const ImuConfig& config, const ModelSpec& model, const std::string& where,
                Diagnostics& diagnostics) {
  if (!model.link(config.frame)) {
    diagnostics.error(where + " <frameName> [" + config.frame + "] is not a link" +
                      didYouMean(config.frame, model.linkNames()));
  }
}

}  // namespace

ImuConfig parseImuSensorConfig(const SensorSpec& sensor, const ModelSpec& model, Diagnostics& diagnostics) {
  ImuConfig config;
  config.link = sensor.link;
  config.pose = sensor.pose;
  config.frame = sensor.link;
  config.update_rate = sensor.update_rate;
  const std::string where = "sensor [" + sensor.name + "] on link [" + sensor.link + "]";
  if (sensor.plugin) {
    PluginTags tags(sensor.plugin->element, where + " plugin [" + sensor.plugin->name + "]", diagnostics);
    config.topic = tags.text("topicName", config.topic);
    config.frame = tags.text("frameName", config.frame);
    config.update_rate = tags.positive("updateRateHZ", config.update_rate, /*allow_zero=*/true);
    config.noise_stddev = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
    config.robot_namespace = tags.text("robotNamespace", "");
    tags.accept(
        {"alwaysOn", "updateRate", "bodyName", "xyzOffset", "rpyOffset", "initialOrientationAsReference"});
    tags.finish();
  }
  checkFrame(config, model, where, diagnostics);
  return config;
}

ImuConfig parseImuPluginConfig(const PluginSpec& plugin, const ModelSpec& model, Diagnostics& diagnostics) {
  ImuConfig config;
  PluginTags tags(plugin.element, "plugin [" + plugin.name + "]", diagnostics);
  config.link = tags.text("bodyName", "");
  if (!model.link(config.link)) {
    diagnostics.error(tags.where() + " <bodyName> [" + config.link + "] is not a link" +
                      didYouMean(config.link, model.linkNames()));
  }
  config.frame = tags.text("frameName", config.link);
  config.topic = tags.text("topicName", config.topic);
  config.update_rate = tags.positive("updateRate", 0, /*allow_zero=*/true);
  config.noise_stddev = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
  config.robot_namespace = tags.text("robotNamespace", "");
  tags.accept({"serviceName", "alwaysOn", "xyzOffsets", "rpyOffsets"});
  tags.finish();
  if (model.link(config.link)) checkFrame(config, model, tags.where(), diagnostics);
  return config;
}

Imu::Imu(std::string name, ImuConfig config, const Eigen::Vector3d& gravity, uint64_t seed)
    : Plugin(std::move(name)),
      config_(std::move(config)),
      gravity_(gravity),
      seed_(seed),
      timer_(config_.update_rate),
      noise_(seed) {
  sample_.frame_id = config_.frame;
  const double variance = config_.noise_stddev * config_.noise_stddev;
  sample_.angular_velocity_variance = sample_.linear_acceleration_variance = variance;
}

void Imu::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer_.due(time)) return;
  const Eigen::Isometry3d frame = body.linkPose(config_.link) * config_.pose;
  const Eigen::Matrix3d to_frame = frame.linear().transpose();
  const Eigen::Vector3d velocity = body.linkLinearVelocity(config_.link);
  const Eigen::Vector3d acceleration =
      last_time_ >= 0 ? Eigen::Vector3d((velocity - last_velocity_) / (time.sim_time - last_time_))
                      : Eigen::Vector3d::Zero();
  last_velocity_ = velocity;
  last_time_ = time.sim_time;

  std::normal_distribution<double> gaussian(0.0, config_.noise_stddev);
  const auto noise = [&] {
    return config_.noise_stddev > 0 ? Eigen::Vector3d(gaussian(noise_), gaussian(noise_), gaussian(noise_))
                                    : Eigen::Vector3d::Zero();
  };
  sample_.stamp = time.sim_time;
  sample_.orientation = Eigen::Quaterniond(frame.linear());
  sample_.angular_velocity = to_frame * body.linkAngularVelocity(config_.link) + noise();
  sample_.linear_acceleration = to_frame * (acceleration - gravity_) + noise();
  ++sample_count_;
}

void Imu::reset() {
  timer_.reset();
  noise_.seed(seed_);
  last_time_ = -1;
  last_velocity_.setZero();
}

}  // namespace bullet_sim
