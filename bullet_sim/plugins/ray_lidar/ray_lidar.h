// A lidar: <sensor type="ray"> (or gpu_ray) with one of Gazebo's laser plugins, whose filename chooses the
// output: libgazebo_ros_laser.so and libgazebo_ros_gpu_laser.so sensor_msgs/LaserScan (the plane at 0
// elevation), the velodyne plugins sensor_msgs/PointCloud2 (x y z intensity ring) and
// libgazebo_ros_block_laser.so sensor_msgs/PointCloud. Its plugin tags are the tag tables in ray_lidar.cpp;
// README.md describes the sensor's <ray> block and the output (REP 117).
#pragma once

#include <random>
#include <string>
#include <vector>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/ray_casting_plugin.h"

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
  std::string topic;
  std::string frame;

  int beams() const;  ///< horizontal beams per channel
};

/// Reads the sensor and plugin tags; the plugin's filename chooses the output.
void parseRayLidar(const DeclarationSource& source, RayLidarConfig& config);

/// Reads a ray sensor's <ray> block (scan, range, noise) into `config`; `where` heads the messages. Counts
/// and ranges are bounded by source.limits. Without `noise_used` (a range plugin ignores the noise, and
/// says so) a negative <stddev> is kept as written, without its own warning.
void readRayTags(const TagNode* sensor, const std::string& where, RayLidarConfig& config,
                 const DeclarationSource& source, bool noise_used = true);

/// The unit direction of every ray of `config`'s scan in the sensor frame, channel-major, bottom channel
/// first; `channels` = 1 takes the plane at 0 elevation.
std::vector<Eigen::Vector3f> rayDirections(const RayLidarConfig& config, int channels);

class RayLidar : public RayCastingPlugin {
 public:
  RayLidar(const PluginDeclaration& declaration, const RayLidarConfig& config, const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const RayLidarConfig& config() const { return config_; }

 private:
  void publishScan(const StepTime& time);
  void publishCloud(const StepTime& time);
  /// What the sensor measures for a true range: REP 117's infinities, noise on in-range values.
  double measured(double range, std::normal_distribution<double>& gaussian);

  RayLidarConfig config_;
  Stream<LaserScan> scan_;
  Stream<PointCloud> cloud_;
  Stream<LegacyPointCloud> legacy_cloud_;
};

}  // namespace bullet_sim
