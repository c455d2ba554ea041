// libhector_gazebo_ros_gps.so (hector_gazebo_plugins on Noetic): a GNSS receiver at the origin of a link,
// publishing sensor_msgs/NavSatFix and its velocity as geometry_msgs/Vector3Stamped.
//
// Tags and defaults (hector's): bodyName [the root link: where the receiver is], frameId [/world: only the
//   messages' label], topicName [fix], velocityTopicName [fix_velocity], updateRate [4 Hz] or updatePeriod,
//   referenceLatitude [49.9 deg], referenceLongitude [8.9 deg], referenceHeading [0 deg: the world's x axis
//   clockwise from north], referenceAltitude [0 m], useWorldSphericalCoordinates [false: when true, the
//   world's <spherical_coordinates> give the reference, which explicit reference tags still override; a world
//   without them is at 0 N 0 E with x east, as in Gazebo], status [0 = STATUS_FIX], service [0],
//   robotNamespace, and two error models (hector_sensor_model.h): the position's (offset, drift,
//   driftFrequency, gaussianNoise, scaleError) and the velocity's (velocityOffset, velocityDrift, ...), each
//   "x y z". The velocity drift integrates into the position drift, as in hector.
// The set_reference_geopose service and the dynamic_reconfigure servers need hector's own types, which Debian
// lacks: one warning says they are left out.
//
// Position: the world position p of the link turns into latitude, longitude and altitude through the WGS84
// radii at the reference latitude, as hector computes them: north = cos(h) p.x + sin(h) p.y, west =
// -sin(h) p.x + cos(h) p.y; latitude = reference + north / R_north, longitude = reference - west / R_east,
// altitude = reference + p.z. The velocity is (north, west, up), as hector publishes it. The covariance is
// diagonal: drift^2 + gaussianNoise^2 per axis.
#pragma once

#include <optional>
#include <string>

#include "bullet_sim/plugins/hector_sensor_model.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

/// Where the world's origin is and which way its x axis points.
struct GeoReference {
  double latitude = 49.9;  ///< [deg]
  double longitude = 8.9;  ///< [deg]
  double heading = 0;      ///< [rad] of the world's x axis, clockwise from north
  double altitude = 0;     ///< [m]
};

struct HectorGpsConfig : PluginConfig {
  std::string frame = "/world";
  std::string fix_topic = "fix";
  std::string velocity_topic = "fix_velocity";
  bool use_world_spherical_coordinates = false;
  /// The reference tags that were given; they override the world's spherical coordinates.
  std::optional<double> latitude, longitude, heading, altitude;
  int status = 0;
  unsigned service = 0;
  SensorErrorConfig position;
  SensorErrorConfig velocity;

  HectorGpsConfig() { update_rate = 4; }
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

  const GeoReference& reference() const { return reference_; }
  const NavSatFixSample& fix() const { return fixes_.latest(); }
  uint64_t fixCount() const { return fixes_.count(); }
  const Vector3Sample& velocity() const { return velocities_.latest(); }

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
