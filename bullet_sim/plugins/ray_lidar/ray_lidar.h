// A lidar: <sensor type="ray"> (or gpu_ray) with one of Gazebo's laser plugins. The plugin filename chooses
// the output, as in Gazebo:
//   libgazebo_ros_laser.so, libgazebo_ros_gpu_laser.so                   sensor_msgs/LaserScan (the plane at
//   0 elevation) libgazebo_ros_velodyne_laser.so, libgazebo_ros_velodyne_gpu_laser.so sensor_msgs/PointCloud2
//   (x y z intensity ring) libgazebo_ros_block_laser.so sensor_msgs/PointCloud
//
// Sensor tags (SDF's): update_rate [Hz], pose, ray/scan/horizontal/{samples [640], resolution [1],
//   min_angle [0], max_angle [0]}, ray/scan/vertical/{samples [1], resolution [1], min_angle [0], max_angle
//   [0]} (channels, bottom first), ray/range/{min, max, resolution}, ray/noise/{type gaussian, mean, stddev}.
// Plugin tags: topicName [scan; Gazebo's "/world" default meant nothing], frameName [the sensor's link],
//   robotNamespace; the velodyne plugins also min_range, max_range [m] and gaussianNoise [m].
// LaserScan follows Gazebo and REP 117: N = samples * resolution beams, angle_increment = (max - min) / (N -
// 1); +inf when nothing is within range max, -inf for a hit closer than range min; noise only on in-range
// values, which are then clamped to [min, max]. Point clouds hold the in-range returns only. Rays hit
// collision geometry; they skip the part the sensor sits on.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/plugins/sensor_interfaces.h"

namespace bullet_sim {

struct RayLidarConfig : PluginConfig {
  enum class Output { kLaserScan, kPointCloud2, kPointCloud };

  int samples = 640;
  double resolution = 1;
  double min_angle = 0;  ///< [rad]
  double max_angle = 0;
  int channels = 1;          ///< vertical samples * resolution
  double min_elevation = 0;  ///< [rad] of the bottom channel
  double max_elevation = 0;
  double range_min = 0;  ///< [m]
  double range_max = 0;
  double noise_mean = 0;  ///< [m]
  double noise_stddev = 0;
  Output output = Output::kLaserScan;
  std::string topic = "scan";
  std::string frame;

  int beams() const;  ///< horizontal beams per channel
};

/// Reads the sensor and plugin tags; the plugin's filename chooses the output.
void parseRayLidar(const DeclarationSource& source, RayLidarConfig& config);

/// Reads a ray sensor's <ray> block (scan, range, noise) into `config`; `where` heads the messages. Counts
/// and ranges are bounded by source.limits.
void readRayTags(const TagNode* sensor, const std::string& where, RayLidarConfig& config,
                 const DeclarationSource& source);

/// The unit direction of every ray of `config`'s scan in the sensor frame, channel-major, bottom channel
/// first; `channels` = 1 takes the plane at 0 elevation.
std::vector<Eigen::Vector3f> rayDirections(const RayLidarConfig& config, int channels);

class RayLidar : public Plugin, public RaySensor {
 public:
  RayLidar(const PluginDeclaration& declaration, const RayLidarConfig& config, const PluginSetup& setup);

  bool castsRays(const StepTime& time) const override { return timer().wouldFire(time); }
  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;
  RayPattern rayPattern(const RobotBody& body) const override;

  const RayLidarConfig& config() const { return config_; }
  /// The direction of every ray in the sensor frame (unit vectors), channel-major, bottom channel first.
  const std::vector<Eigen::Vector3f>& directions() const { return directions_; }
  /// The latest scan (LaserScan output).
  const LaserScan& scan() const { return scan_.latest(); }
  /// The latest point cloud (point-cloud outputs).
  const PointCloud& cloud() const;
  /// How many scans or clouds there were.
  uint64_t scanCount() const { return scan_.count() + cloud_.count() + legacy_cloud_.count(); }

 private:
  void publishScan(const StepTime& time, const Eigen::Isometry3d& sensor);
  void publishCloud(const StepTime& time, const Eigen::Isometry3d& sensor);
  /// What the sensor measures for a true range: REP 117's infinities, noise on in-range values.
  double measured(double range, std::normal_distribution<double>& gaussian);

  RayLidarConfig config_;
  BodyId own_body_;
  std::vector<Eigen::Vector3f> directions_;  ///< per ray, in the sensor frame, channel-major
  std::vector<Eigen::Vector3f> world_directions_;
  std::vector<double> ranges_;
  Stream<LaserScan> scan_;
  Stream<PointCloud> cloud_;
  Stream<LegacyPointCloud> legacy_cloud_;
};

}  // namespace bullet_sim
