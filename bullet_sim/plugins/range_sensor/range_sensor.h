// A ranger (ultrasound or infrared): <sensor type="ray"> with libgazebo_ros_range.so publishes
// sensor_msgs/Range, the nearest hit over all of the sensor's rays. Its plugin tags are kRangeTags in
// range_sensor.cpp; README.md describes the sensor's <ray> block and how the range is measured.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"
#include "plugins/ray_lidar/ray_lidar.h"

namespace bullet_sim {

struct RangeConfig : PluginConfig {
  RayLidarConfig rays;  ///< the sensor's link, pose, scan and range
  std::string topic;
  std::string frame;
  bool infrared = false;
  double field_of_view = 0;  ///< [rad]
  double noise_stddev = 0;   ///< [m]
};

void parseRange(const DeclarationSource& source, RangeConfig& config);
/// The rays of a range plugin `plugin` (by `author`, e.g. "Gazebo's") on its ray sensor: they must reach past
/// their minimum, and the sensor's <noise>, which the plugin never reads, is ignored with a warning.
void readRangeRays(const DeclarationSource& source, RangeConfig& config, const std::string& plugin,
                   const std::string& author);

class RangeSensor : public RayCastingPlugin {
 public:
  RangeSensor(const PluginDeclaration& declaration, const RangeConfig& config, const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const RangeConfig& config() const { return config_; }

 protected:
  /// What the sensor reads at `sim_time` [s] for the nearest true hit [m].
  virtual double measured(double nearest, double sim_time);

 private:
  RangeConfig config_;
  Stream<RangeSample> samples_;
};

}  // namespace bullet_sim
