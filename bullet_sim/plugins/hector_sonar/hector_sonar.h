// hector_gazebo_plugins' sonar: <sensor type="ray"> with libhector_gazebo_ros_sonar.so publishes
// sensor_msgs/Range (ultrasound), the nearest hit over all of the sensor's rays, cast as range_sensor casts
// them, with hector's error model (offset, drift, white noise, scale) on ranges below the maximum, which are
// then clamped to [min, max]. Its tags, hector's with their defaults, are hectorSonarTags() in
// hector_sonar.cpp.
#pragma once

#include "bullet_sim/plugins/hector_sensor_model.h"
#include "plugins/range_sensor/range_sensor.h"

namespace bullet_sim {

struct HectorSonarConfig : RangeConfig {
  SensorErrorConfig error;  ///< scalar: x only
};

void parseHectorSonar(const DeclarationSource& source, HectorSonarConfig& config);

class HectorSonar : public RangeSensor {
 public:
  HectorSonar(const PluginDeclaration& declaration, const HectorSonarConfig& config,
              const PluginSetup& setup);

 private:
  double measured(double nearest, double sim_time) override;
  void onReset() override;

  SensorError error_;
  double last_update_ = -1;  ///< [s] sim time of the last range; < 0 before the first
};

}  // namespace bullet_sim
