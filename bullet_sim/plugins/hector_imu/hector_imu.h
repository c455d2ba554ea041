// libhector_gazebo_ros_imu.so (hector_gazebo_plugins on Noetic): sensor_msgs/Imu of a link, with hector's
// error models on the acceleration, the rates and the yaw (hector_sensor_model.h). Its tags are the table in
// hector_imu.cpp; README.md says what each update measures.
#pragma once

#include <string>

#include "bullet_sim/plugins/hector_sensor_model.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct HectorImuConfig : PluginConfig {
  std::string frame;
  std::string topic;
  std::string bias_topic;  ///< "" publishes no biases
  std::string service;     ///< "" serves no calibration
  Eigen::Quaterniond rpy_offset = Eigen::Quaterniond::Identity();
  SensorErrorConfig accel;
  SensorErrorConfig rate;
  SensorErrorConfig yaw;  ///< x only
};

void parseHectorImu(const DeclarationSource& source, HectorImuConfig& config);

class HectorImu : public Plugin {
 public:
  HectorImu(const PluginDeclaration& declaration, const HectorImuConfig& config, const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const HectorImuConfig& config() const { return config_; }
  /// The calibrate service: the rate drift back to zero, as hector does.
  void calibrate();

 private:
  void onReset() override;
  void publishBias(const Eigen::Quaterniond& orientation_error);

  HectorImuConfig config_;
  Eigen::Vector3d gravity_;
  SensorError accel_error_;
  SensorError rate_error_;
  SensorError yaw_error_;
  Eigen::Vector3d last_velocity_ = Eigen::Vector3d::Zero();  ///< [m/s] world, at the last update
  double last_update_ = -1;                                   ///< [s]; -1 before the first
  Stream<ImuSample> samples_;
  Stream<ImuSample> biases_;
};

}  // namespace bullet_sim
