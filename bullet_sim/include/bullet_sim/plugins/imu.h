// An IMU: <sensor type="imu"> with libgazebo_ros_imu_sensor.so, or the model plugin libgazebo_ros_imu.so.
// Sensor plugin tags: topicName [imu], frameName [the sensor's link], updateRateHZ [the sensor's
// update_rate],
//   gaussianNoise [0], robotNamespace. Model plugin tags: bodyName, topicName, frameName, updateRate,
//   gaussianNoise. Noise goes on angular velocity and linear acceleration; the orientation is exact.
// Linear acceleration is measured, as a real IMU does: at rest it reads +g upwards.
#pragma once

#include <random>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct ImuConfig {
  std::string link;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the link frame
  double update_rate = 0;                                  ///< [Hz]; 0 = every step
  double noise_stddev = 0;
  std::string topic = "imu";
  std::string frame;
  std::string robot_namespace;
};

ImuConfig parseImuSensorConfig(const SensorSpec& sensor, const ModelSpec& model, Diagnostics& diagnostics);
ImuConfig parseImuPluginConfig(const PluginSpec& plugin, const ModelSpec& model, Diagnostics& diagnostics);

class Imu : public Plugin {
 public:
  Imu(std::string name, ImuConfig config, const Eigen::Vector3d& gravity, uint64_t seed);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;
  void reset() override;

  const ImuConfig& config() const { return config_; }
  const ImuSample& sample() const { return sample_; }
  uint64_t sampleCount() const { return sample_count_; }

 private:
  ImuConfig config_;
  Eigen::Vector3d gravity_;
  uint64_t seed_;
  UpdateTimer timer_;
  std::mt19937_64 noise_;
  Eigen::Vector3d last_velocity_ = Eigen::Vector3d::Zero();
  double last_time_ = -1;
  ImuSample sample_;
  uint64_t sample_count_ = 0;
};

}  // namespace bullet_sim
