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

namespace bullet_sim {

struct RayLidarConfig {
  enum class Output { kLaserScan, kPointCloud2, kPointCloud };

  std::string link;                                        ///< the link the sensor is on
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor frame in the link frame
  double update_rate = 0;                                  ///< [Hz]; 0 = every step
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
  std::string robot_namespace;

  int beams() const;  ///< horizontal beams per channel
};

/// Reads the sensor and plugin tags; problems go to `diagnostics`.
RayLidarConfig parseRayLidarConfig(const SensorSpec& sensor, const ModelSpec& model,
                                   Diagnostics& diagnostics);

class RayLidar : public Plugin {
 public:
  /// `own_body`: the ray-caster body of the part the sensor sits on, which its rays skip.
  RayLidar(std::string name, RayLidarConfig config, BodyId own_body, uint64_t seed);

  bool castsRays(const StepTime& time) const override { return timer_.wouldFire(time); }
  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;
  void reset() override;

  const RayLidarConfig& config() const { return config_; }
  /// The latest scan: a LaserScan output, or for point clouds the ranges of every ray (channel-major).
  const LaserScan& scan() const { return scan_; }
  /// The latest point cloud (point-cloud outputs only).
  const PointCloud& cloud() const { return cloud_; }
  uint64_t scanCount() const { return scan_count_; }

 private:
  RayLidarConfig config_;
  BodyId own_body_;
  uint64_t seed_;
  UpdateTimer timer_;
  std::mt19937_64 noise_;
  std::vector<Eigen::Vector3f> directions_;  ///< per ray, in the sensor frame, channel-major
  std::vector<Eigen::Vector3f> world_directions_;
  std::vector<double> ranges_;
  LaserScan scan_;
  PointCloud cloud_;
  uint64_t scan_count_ = 0;
};

}  // namespace bullet_sim
