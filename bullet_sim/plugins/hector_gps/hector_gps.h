// libhector_gazebo_ros_gps.so (hector_gazebo_plugins on Noetic): a GNSS receiver at the origin of a link,
// publishing sensor_msgs/NavSatFix and its velocity as geometry_msgs/Vector3Stamped, with hector's error
// models on both (hector_sensor_model.h). Its tags are the table in hector_gps.cpp; README.md gives the
// geodesy.
#pragma once

#include <optional>
#include <string>

#include "bullet_sim/plugins/hector_sensor_model.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

/// Where the world's origin is and which way its x axis points; hector's defaults (the tag table's).
struct GeoReference {
  double latitude = 49.9;  ///< [deg]
  double longitude = 8.9;  ///< [deg]
  double heading = 0;      ///< [rad] of the world's x axis, clockwise from north
  double altitude = 0;     ///< [m]
};

struct HectorGpsConfig : PluginConfig {
  std::string frame;
  std::string fix_topic;
  std::string velocity_topic;
  bool use_world_spherical_coordinates = false;
  /// The reference, as the tags give it; with the world's spherical coordinates, only the tags given, which
  /// override the world's.
  std::optional<double> latitude, longitude, heading, altitude;
  int status = 0;
  unsigned service = 0;
  SensorErrorConfig position;
  SensorErrorConfig velocity;
};

void parseHectorGps(const DeclarationSource& source, HectorGpsConfig& config);

/// The reference a GPS uses: hector's defaults, then the world's spherical coordinates when the config asks
/// for them (`world`, or Gazebo's defaults without it), then the config's own reference tags.
GeoReference geoReference(const HectorGpsConfig& config, const std::optional<SphericalCoordinates>& world);

/// hector's local WGS84 radii at `latitude` [deg]: the meridian's (north) and the parallel's (east) [m].
Eigen::Vector2d earthRadii(double latitude);

class HectorGps : public Plugin {
 public:
  HectorGps(const PluginDeclaration& declaration, const HectorGpsConfig& config, const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

 private:
  void onReset() override;

  HectorGpsConfig config_;
  GeoReference reference_;
  Eigen::Vector2d radii_;  ///< [m] north, east
  SensorError position_error_;
  SensorError velocity_error_;
  double last_update_ = -1;  ///< [s]; -1 before the first
  Stream<NavSatFixSample> fixes_;
  Stream<Vector3Sample> velocities_;
};

}  // namespace bullet_sim
