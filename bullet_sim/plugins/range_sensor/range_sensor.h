// A ranger (ultrasound or infrared): <sensor type="ray"> with libgazebo_ros_range.so publishes
// sensor_msgs/Range, the nearest hit over all of the sensor's rays.
//
// Sensor tags (SDF's, as for a lidar): update_rate [Hz], pose, ray/scan/horizontal and ray/scan/vertical
//   (samples, resolution, min_angle, max_angle: every ray of both counts), ray/range/{min, max}.
// Plugin tags (gazebo_plugins' names and defaults): topicName [range; Gazebo's is /range, which ignores the
//   namespace], frameName [the sensor's link; Gazebo's /world meant nothing], radiation [ultrasound;
//   anything else is infrared, as in Gazebo], fov [0.05 rad: the message's field_of_view, whatever the rays
//   span], gaussianNoise [0 m], updateRate [0 = the sensor's; the slower of the two wins], robotNamespace.
// The range: nothing within range max reads range max (as Gazebo's plugin has it); a hit closer than range
// min reads -inf (REP 117); noise goes only on in-range values, which are then clamped to [min, max]. The
// ray sensor's own <noise> does not reach this output, as in Gazebo (a warning says so).
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"
#include "plugins/ray_lidar/ray_lidar.h"

namespace bullet_sim {

struct RangeConfig : PluginConfig {
  RayLidarConfig rays;  ///< the sensor's link, pose, scan and range
  std::string topic = "range";
  std::string frame;
  bool infrared = false;
  double field_of_view = 0.05;  ///< [rad]
  double noise_stddev = 0;      ///< [m]
};

void parseRange(const DeclarationSource& source, RangeConfig& config);

class RangeSensor : public Plugin, public RaySensor {
 public:
  RangeSensor(const PluginDeclaration& declaration, const RangeConfig& config, const PluginSetup& setup);

  bool castsRays(const StepTime& time) const override { return timer().wouldFire(time); }
  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;
  RayPattern rayPattern(const RobotBody& body) const override;

  const RangeConfig& config() const { return config_; }
  const RangeSample& sample() const { return samples_.latest(); }
  uint64_t sampleCount() const { return samples_.count(); }

 private:
  /// What the sensor reads for the nearest true hit [m].
  double measured(double nearest);

  RangeConfig config_;
  BodyId own_body_;
  std::vector<Eigen::Vector3f> directions_;  ///< in the sensor frame
  std::vector<Eigen::Vector3f> world_directions_;
  std::vector<double> ranges_;
  Stream<RangeSample> samples_;
};

}  // namespace bullet_sim
