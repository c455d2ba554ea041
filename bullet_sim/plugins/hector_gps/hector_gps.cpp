#include "plugins/hector_gps/hector_gps.h"

#include "bullet_sim/plugins/registry.h"

#include <cmath>

namespace bullet_sim {

namespace {

// WGS84.
constexpr double kEquatorialRadius = 6378137.0;  // [m]
constexpr double kFlattening = 1.0 / 298.257223563;
constexpr double kEccentricity2 = 2 * kFlattening - kFlattening * kFlattening;
constexpr double kDegree = M_PI / 180;

TagTable hectorGpsTags() {
  const std::string reference =
      "the world's origin; with useWorldSphericalCoordinates, it overrides the world's";
  const std::vector<TagRow> own = {
      {"frameId", TagType::kFrame, "/world", "", "the messages' frame_id only", ""},
      {"topicName", TagType::kTopic, "fix", "", "the topic of the sensor_msgs/NavSatFix", ""},
      {"velocityTopicName", TagType::kTopic, "fix_velocity", "",
       "the topic of the velocity (north, west, up) as a geometry_msgs/Vector3Stamped", ""},
      {"useWorldSphericalCoordinates", TagType::kFlag, "false", "",
       "true: the world's <spherical_coordinates> are the reference",
       "the same; a world without them is at 0 N 0 E with x east, as in Gazebo"},
      {"referenceLatitude", TagType::kNumber, "49.9", "deg", "the latitude of " + reference, ""},
      {"referenceLongitude", TagType::kNumber, "8.9", "deg", "the longitude of " + reference, ""},
      {"referenceHeading", TagType::kNumber, "0", "deg",
       "the world's x axis clockwise from north; with useWorldSphericalCoordinates, it overrides the world's",
       ""},
      {"referenceAltitude", TagType::kNumber, "0", "m", "the altitude of " + reference, ""},
      {"status", TagType::kNumber, "0", "", "the fix's status (-1 no fix, 0 fix, 1 SBAS, 2 GBAS)",
       "the same, with a warning for another number"},
      {"service", TagType::kPositive, "0", "",
       "the fix's service bits (1 GPS, 2 GLONASS, 4 COMPASS, 8 GALILEO)", ""},
      {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
  };
  TagTable table;
  for (const auto& rows : {hectorBodyAndTimerRows("4"), own, sensorErrorRows("", /*vector=*/true, "m"),
                           sensorErrorRows("velocity", /*vector=*/true, "m/s")}) {
    for (const TagRow& row : rows) table.add(row);
  }
  return table;
}

/// The reference tags: each given one, and each one when the world does not give the reference.
void readReference(PluginTags& tags, HectorGpsConfig& config) {
  const auto read = [&](const char* tag, std::optional<double>& value) {
    if (!config.use_world_spherical_coordinates || tags.has(tag)) value = tags.number(tag);
  };
  read("referenceLatitude", config.latitude);
  read("referenceLongitude", config.longitude);
  read("referenceHeading", config.heading);
  read("referenceAltitude", config.altitude);
}

}  // namespace

void parseHectorGps(const DeclarationSource& source, HectorGpsConfig& config) {
  PluginTags& tags = source.tags;
  config.link = readHectorBody(source);
  config.frame = tags.frame("frameId", tags.table()->row("frameId")->fallback, /*gazebo_drops_slash=*/false);
  config.fix_topic = tags.text("topicName");
  config.velocity_topic = tags.text("velocityTopicName");
  config.update_rate = readHectorUpdateRate(tags);
  config.use_world_spherical_coordinates = tags.flag("useWorldSphericalCoordinates");
  readReference(tags, config);
  if (config.latitude && std::abs(*config.latitude) >= 90) {
    source.diagnostics.error(tags.where() + " <referenceLatitude> must lie strictly between -90 and 90 deg");
  }
  config.status = static_cast<int>(tags.number("status"));
  if (config.status < -1 || config.status > 2) {
    source.diagnostics.warning(tags.where() + " <status> " + std::to_string(config.status) +
                               " is no NavSatStatus (-1 no fix, 0 fix, 1 SBAS fix, 2 GBAS fix): published as "
                               "is");
  }
  config.service = static_cast<unsigned>(tags.nonNegative("service"));
  config.position = readSensorError(tags, "", /*vector=*/true);
  config.velocity = readSensorError(tags, "velocity", /*vector=*/true);
  source.diagnostics.warning(tags.where() + " hector's [" + config.fix_topic +
                             "/set_reference_geopose] service and its dynamic_reconfigure servers need "
                             "hector's own types, which Debian lacks: left out");
}

GeoReference geoReference(const HectorGpsConfig& config, const std::optional<SphericalCoordinates>& world) {
  GeoReference reference;
  if (config.use_world_spherical_coordinates) {
    const SphericalCoordinates earth = world.value_or(SphericalCoordinates{});
    reference.latitude = earth.latitude;
    reference.longitude = earth.longitude;
    reference.altitude = earth.elevation;
    reference.heading = M_PI / 2 - earth.heading;  // SDF's is counter-clockwise from east
  }
  if (config.latitude) reference.latitude = *config.latitude;
  if (config.longitude) reference.longitude = *config.longitude;
  if (config.heading) reference.heading = *config.heading * kDegree;
  if (config.altitude) reference.altitude = *config.altitude;
  return reference;
}

Eigen::Vector2d earthRadii(double latitude) {
  const double sine = std::sin(latitude * kDegree);
  const double temp = 1.0 / (1.0 - kEccentricity2 * sine * sine);
  const double prime_vertical = kEquatorialRadius * std::sqrt(temp);
  return {prime_vertical * (1 - kEccentricity2) * temp, prime_vertical * std::cos(latitude * kDegree)};
}

HectorGps::HectorGps(const PluginDeclaration& declaration, const HectorGpsConfig& config,
                     const PluginSetup& setup)
    : Plugin(declaration, setup),
      config_(config),
      reference_(geoReference(config, setup.spherical_coordinates)),
      radii_(earthRadii(reference_.latitude)),
      position_error_(config.position),
      velocity_error_(config.velocity) {
  NavSatFixSample& fix = fixes_.next();
  fix.frame_id = velocities_.next().frame_id = config_.frame;
  fix.status = config_.status;
  fix.service = config_.service;
  fix.position_covariance_type = 2;  // COVARIANCE_TYPE_DIAGONAL_KNOWN
  for (int i = 0; i < 3; ++i) {
    fix.position_covariance[4 * i] = config_.position.drift[i] * config_.position.drift[i] +
                                     config_.position.gaussian_noise[i] * config_.position.gaussian_noise[i];
  }
  addOutput(config_.fix_topic, fixes_);
  addOutput(config_.velocity_topic, velocities_);
  onReset();
}

void HectorGps::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer().due(time)) return;
  const double dt = last_update_ >= 0 ? time.sim_time - last_update_ : 0.0;
  last_update_ = time.sim_time;
  const Eigen::Vector3d velocity =
      velocity_error_.apply(body.linkLinearVelocity(config_.link), dt, noise());
  const Eigen::Vector3d position =
      position_error_.apply(body.linkPose(config_.link).translation(), dt, noise());
  // A drift of the velocity moves the position for the next update.
  position_error_.setDrift(position_error_.drift() + dt * velocity_error_.drift());

  const double c = std::cos(reference_.heading), s = std::sin(reference_.heading);
  NavSatFixSample& fix = fixes_.next();
  fix.stamp = time.sim_time;
  fix.latitude = reference_.latitude + (c * position.x() + s * position.y()) / radii_.x() / kDegree;
  fix.longitude = reference_.longitude - (-s * position.x() + c * position.y()) / radii_.y() / kDegree;
  fix.altitude = reference_.altitude + position.z();
  fixes_.publish();
  Vector3Sample& north_west_up = velocities_.next();
  north_west_up.stamp = time.sim_time;
  north_west_up.vector = {c * velocity.x() + s * velocity.y(), -s * velocity.x() + c * velocity.y(),
                          velocity.z()};
  velocities_.publish();
}

void HectorGps::onReset() {
  last_update_ = -1;
  position_error_.reset(noise());
  velocity_error_.reset(noise());
}

BULLET_SIM_PLUGIN_FOLDER(hector_gps) {
  PluginType type = pluginType<HectorGps>("libhector_gazebo_ros_gps.so", parseHectorGps, hectorGpsTags());
  type.needs = kNeedGeodesy;
  type.tf_prefix = TfPrefixRule::kNone;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
