// What scenes, benchmarks and checks ask of a sensor beyond its outputs, by interface and never by a plugin's
// concrete class: where a ray sensor casts, and what a camera sees. A plugin implements the ones it is.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "bullet_sim/physics/robot_body.h"
#include "bullet_sim/plugins/image_source.h"

namespace bullet_sim {

/// The rays a sensor casts per scan, where it is now.
struct RayPattern {
  std::string link;  ///< the link it sits on
  Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();  ///< its frame in the world
  std::vector<Eigen::Vector3f> directions;                   ///< unit, in the world frame
  double range_max = 0;                                      ///< [m]
  double update_rate = 0;                                    ///< [Hz] of its scans
};

/// A sensor that casts rays (a lidar, a ranger).
class RaySensor {
 public:
  virtual ~RaySensor() = default;
  /// Its rays at `body`'s current pose.
  virtual RayPattern rayPattern(const RobotBody& body) const = 0;
};

/// A sensor that renders the world (a camera, a depth camera).
class CameraSensor {
 public:
  virtual ~CameraSensor() = default;
  /// Its <cameraName>; "" when it has none.
  virtual const std::string& cameraName() const = 0;
  /// Whether it also measures depth.
  virtual bool measuresDepth() const = 0;
  /// The depths [m] its depth image spans: nearer is white, farther black.
  virtual std::pair<double, double> depthSpan() const = 0;
  /// What it asks its image source for at `body`'s current pose, with or without depth.
  virtual ImageRequest imageRequest(const RobotBody& body, bool depth) const = 0;
};

}  // namespace bullet_sim
