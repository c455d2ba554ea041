// An IMU: <sensor type="imu"> with libgazebo_ros_imu_sensor.so, or the model plugin libgazebo_ros_imu.so,
// publishing sensor_msgs/Imu. Their tags are kImuSensorTags and kImuPluginTags in imu.cpp. Noise goes on the
// angular velocity and the linear acceleration; the orientation is exact. The linear acceleration is measured
// as a real IMU measures it: at rest it reads +g upwards.
#pragma once

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct ImuConfig : PluginConfig {
  double noise_stddev = 0;  ///< [rad/s], [m/s^2]
  std::string topic;
  std::string frame;
};

void parseImuSensor(const DeclarationSource& source, ImuConfig& config);
void parseImuPlugin(const DeclarationSource& source, ImuConfig& config);

class Imu : public Plugin {
 public:
  Imu(const PluginDeclaration& declaration, const ImuConfig& config, const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const ImuConfig& config() const { return config_; }

 private:
  void onReset() override;

  ImuConfig config_;
  Eigen::Vector3d gravity_;
  Eigen::Vector3d last_velocity_ = Eigen::Vector3d::Zero();
  double last_time_ = -1;
  Stream<ImuSample> samples_;
};

}  // namespace bullet_sim
