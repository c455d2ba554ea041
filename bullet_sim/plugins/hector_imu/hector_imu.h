// libhector_gazebo_ros_imu.so (hector_gazebo_plugins on Noetic): sensor_msgs/Imu of a link, with hector's
// error models on the acceleration, the rates and the yaw.
//
// Tags and defaults (hector's): bodyName [the root link], frameId [bodyName], topicName [imu], biasTopicName
//   [<topicName>/bias: the current biases as a sensor_msgs/Imu], serviceName [<topicName>/calibrate:
//   std_srvs/Empty, zeroes the rate drift], updateRate [0 = every step] or updatePeriod, robotNamespace,
//   rpyOffset [0 0 0: turns the reading, as hector does], xyzOffset (read, and without effect, as in hector),
//   gaussianNoise (the old gazebo_ros_imu tag: when not 0, the accel and rate white noise), and the error
//   models (see hector_sensor_model.h) accel* and rate* ("x y z") and yaw* (one number).
// headingDrift and headingGaussianNoise, which older descriptions (Husky's) write and today's hector ignores,
// are read as yawDrift and yawGaussianNoise (unless those are given), with a warning each. The set_accel_bias
// and set_rate_bias services and the dynamic_reconfigure servers need hector's own types, which Debian lacks:
// one warning says they are left out.
//
// Each update: the orientation is the link's, turned by rpyOffset, then by hector's pseudo-AHRS error (the
// yaw bias about z, the accel bias as roll and pitch); the rates are the link's angular velocity in its
// frame; the acceleration is the change of the link's velocity since the last update minus gravity (+g up at
// rest), in the sensor frame. Covariances as hector fills them.
#pragma once

#include <string>

#include "bullet_sim/plugins/hector_sensor_model.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct HectorImuConfig : PluginConfig {
  std::string frame;
  std::string topic = "imu";
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
  const ImuSample& sample() const { return samples_.latest(); }
  uint64_t sampleCount() const { return samples_.count(); }
  /// The biases: orientation error, rate and acceleration biases.
  const ImuSample& bias() const { return biases_.latest(); }
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
