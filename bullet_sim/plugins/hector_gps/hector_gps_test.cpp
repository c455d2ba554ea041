// hector's GPS against WGS84's radii of curvature, on the multi-sensor test robot
// (test/fixtures/robots/multi_sensor_robot.urdf.xacro), at rest and moving: reference, heading, the world's
// spherical coordinates, drift and load messages. Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/hector_gps/hector_gps.h"
#include "plugins/planar_move/planar_move.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using test::loadErrors;
using test::loadWarnings;
using test::multiSensorRobot;
using test::multiSensorUrdf;
using test::parseExpecting;
using test::withoutPluginTags;

using ::testing::Contains;
using ::testing::HasSubstr;
using ::testing::IsSupersetOf;

constexpr double kDegree = M_PI / 180;
const std::string kGpsPlugin = "libhector_gazebo_ros_gps.so";
constexpr double kGpsHeight = 0.2;  // [m] of gps_link above base_footprint

/// The multi-sensor robot's GPS without drift, with `tags`.
std::string idealGps(const test::Tags& tags = {}) {
  test::Tags all = {{"drift", "0 0 0"}};
  all.insert(all.end(), tags.begin(), tags.end());
  return test::withPluginTags(multiSensorUrdf(), kGpsPlugin, all);
}

/// The first fix of the GPS of the robot `urdf` spawned at `pose` in `world`.
NavSatFixSample firstFix(const std::string& urdf, const SpawnPose& pose,
                         WorldSpec world = test::shippedWorld("empty.world")) {
  Simulation simulation(std::move(world));
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "gps"), pose);
  const HectorGps& gps = *test::pluginsOf<HectorGps>(robot).at(0);
  test::stepUntil(simulation, [&] { return test::countOf<NavSatFixSample>(gps) > 0; }, 1.0, "a fix");
  return test::latestOf<NavSatFixSample>(gps);
}

// WGS84's radii of curvature at a latitude [deg]: the meridian's, and the parallel's.
constexpr double kA = 6378137.0;
constexpr double kE2 = 6.69437999014e-3;
double meridianRadius(double latitude) {
  return kA * (1 - kE2) / std::pow(1 - kE2 * std::pow(std::sin(latitude * kDegree), 2), 1.5);
}
double parallelRadius(double latitude) {
  return kA * std::cos(latitude * kDegree) / std::sqrt(1 - kE2 * std::pow(std::sin(latitude * kDegree), 2));
}

TEST(HectorGps, AHundredMetresNorthChangesTheLatitudeAsTheMeridianRadiusPredicts) {
  const NavSatFixSample origin = firstFix(idealGps(), {});
  const NavSatFixSample north = firstFix(idealGps(), {.x = 100});
  EXPECT_NEAR(origin.latitude, 49.9, 1e-8);
  EXPECT_NEAR(origin.longitude, 8.9, 1e-8);
  EXPECT_NEAR(origin.altitude, kGpsHeight, 1e-3);
  EXPECT_NEAR(north.latitude - origin.latitude, 100 / meridianRadius(49.9) / kDegree, 1e-8);
  EXPECT_NEAR(north.longitude, origin.longitude, 1e-8);
  EXPECT_EQ(origin.frame_id, "gps_link");
  EXPECT_EQ(origin.status, 0) << "STATUS_FIX";
  EXPECT_EQ(origin.position_covariance_type, 2) << "COVARIANCE_TYPE_DIAGONAL_KNOWN";
  // +y is west.
  const NavSatFixSample west = firstFix(idealGps(), {.y = 100});
  EXPECT_NEAR(west.longitude - origin.longitude, -100 / parallelRadius(49.9) / kDegree, 1e-8);
  EXPECT_NEAR(west.latitude, origin.latitude, 1e-8);
}

TEST(HectorGps, HeadingAndAltitudeAreHonoured) {
  // The world's x axis points east (90 deg clockwise from north), so its y axis points north.
  const std::string urdf = idealGps({{"referenceLatitude", "-33.9"}, {"referenceLongitude", "151.2"},
                                     {"referenceHeading", "90"}, {"referenceAltitude", "500"}});
  const NavSatFixSample origin = firstFix(urdf, {});
  const NavSatFixSample east = firstFix(urdf, {.x = 100});
  const NavSatFixSample north = firstFix(urdf, {.y = 100});
  EXPECT_NEAR(origin.altitude, 500 + kGpsHeight, 1e-3);
  EXPECT_NEAR(east.longitude - origin.longitude, 100 / parallelRadius(-33.9) / kDegree, 1e-8);
  EXPECT_NEAR(east.latitude, origin.latitude, 1e-8);
  EXPECT_NEAR(north.latitude - origin.latitude, 100 / meridianRadius(-33.9) / kDegree, 1e-8);
  EXPECT_NEAR(north.longitude, origin.longitude, 1e-8);
}

TEST(HectorGps, TheWorldsSphericalCoordinatesGiveTheReferenceOnlyWhenAsked) {
  const WorldSpec zurich = loadWorld(test::fixture("worlds/spherical_coordinates.world"),
                                     PackageResolver::fromEnvironment(), nullptr);
  ASSERT_TRUE(zurich.spherical_coordinates);
  EXPECT_DOUBLE_EQ(zurich.spherical_coordinates->latitude, 47.3977);
  // Without useWorldSphericalCoordinates the plugin's own reference holds.
  EXPECT_NEAR(firstFix(idealGps(), {}, zurich).latitude, 49.9, 1e-8);
  // With it, the world's (SDF heading 0: x east); explicit reference tags would still override it.
  const std::string urdf =
      withoutPluginTags(idealGps({{"useWorldSphericalCoordinates", "true"}}), kGpsPlugin,
                        {"referenceLatitude", "referenceLongitude", "referenceHeading", "referenceAltitude"});
  const NavSatFixSample origin = firstFix(urdf, {}, zurich);
  const NavSatFixSample east = firstFix(urdf, {.x = 100}, zurich);
  EXPECT_NEAR(origin.latitude, 47.3977, 1e-8);
  EXPECT_NEAR(origin.longitude, 8.5456, 1e-8);
  EXPECT_NEAR(origin.altitude, 408 + kGpsHeight, 1e-3);
  EXPECT_NEAR(east.longitude - origin.longitude, 100 / parallelRadius(47.3977) / kDegree, 1e-8);
  HectorGpsConfig asked;
  asked.use_world_spherical_coordinates = true;
  EXPECT_DOUBLE_EQ(geoReference(asked, std::nullopt).heading, M_PI / 2) << "Gazebo's default world: x east";
  asked.latitude = 10;
  EXPECT_DOUBLE_EQ(geoReference(asked, zurich.spherical_coordinates).latitude, 10) << "explicit tags win";
}

TEST(HectorGps, DriftIsSeededAndShowsInTheCovariance) {
  const auto fixes = [](uint64_t seed) {
    Simulation simulation(test::shippedWorld("empty.world"), {.seed = seed});
    Robot& robot = simulation.spawn("robot", multiSensorRobot(), {});
    const HectorGps& gps = *test::pluginsOf<HectorGps>(robot).at(0);
    std::vector<double> latitudes;
    while (latitudes.size() < 20) {
      const uint64_t count = test::countOf<NavSatFixSample>(gps);
      simulation.step();
      if (test::countOf<NavSatFixSample>(gps) != count)
        latitudes.push_back(test::latestOf<NavSatFixSample>(gps).latitude);
    }
    EXPECT_DOUBLE_EQ(test::latestOf<NavSatFixSample>(gps).position_covariance[0], 0.0001 * 0.0001);
    return latitudes;
  };
  const std::vector<double> first = fixes(21);
  EXPECT_EQ(first, fixes(21));
  EXPECT_NE(first, fixes(22));
  EXPECT_NE(first.front(), 49.9) << "the drift starts at N(0, 0.0001^2) m";
  EXPECT_NEAR(first.front(), 49.9, 5 * 0.0001 / meridianRadius(49.9) / kDegree);
}

TEST(HectorGps, LoadMessages) {
  EXPECT_THAT(loadWarnings(idealGps()),
              Contains(HasSubstr("hector's [navsat/fix/set_reference_geopose] service and its "
                                 "dynamic_reconfigure servers need hector's own types, which Debian lacks: "
                                 "left out")));
  const std::string bad =
      idealGps({{"bodyName", "gps_lnk"}, {"velocityDrift", "1"}, {"referenceLatitude", "91"}});
  EXPECT_THAT(loadErrors(bad),
              IsSupersetOf({HasSubstr("<velocityDrift> must be three numbers (x y z), not [1]"),
                            HasSubstr("<referenceLatitude> must lie strictly between -90 and 90 deg")}));
  EXPECT_THAT(loadWarnings(idealGps({{"bodyName", "/gps_lnk"}})),
              IsSupersetOf({HasSubstr("<bodyName> [/gps_lnk] is read as [gps_lnk]: tf2 frame ids have no "
                                      "leading / (Gazebo's plugin keeps it)"),
                            HasSubstr("<bodyName> [gps_lnk] is not a link of the robot (did you mean "
                                      "[gps_link]?)")}));
}

// On the moving robot.

TEST(HectorGps, TheVelocityReadsNorthAndWest) {
  const std::string urdf =
      test::withPluginTags(multiSensorUrdf(), "libhector_gazebo_ros_gps.so", {{"drift", "0 0 0"}});
  for (const auto& [command, north_west] :
       {std::make_pair(test::twist(0.3, 0, 0), Eigen::Vector3d(0.3, 0, 0)),
        std::make_pair(test::twist(0, 0.3, 0), Eigen::Vector3d(0, 0.3, 0))}) {
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "gps"), {});
    test::drivePlanar(simulation, *test::pluginsOf<PlanarMove>(robot).at(0), command, 1.0);
    const Vector3Sample& velocity = test::latestOf<Vector3Sample>(*test::pluginsOf<HectorGps>(robot).at(0));
    EXPECT_LT((velocity.vector - north_west).norm(), 1e-3) << velocity.vector.transpose();
    EXPECT_EQ(velocity.frame_id, "gps_link");
  }
}

}  // namespace
}  // namespace bullet_sim
