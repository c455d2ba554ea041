// Gazebo's rangers, hector's IMU and GPS, and bumpers against analytic truth, on the multi-sensor test robot
// (test/fixtures/robots/multi_sensor_robot.urdf.xacro). Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "bullet_sim/model/gazebo_names.h"
#include "plugins/bumper/bumper.h"
#include "plugins/hector_gps/hector_gps.h"
#include "plugins/hector_imu/hector_imu.h"
#include "plugins/range_sensor/range_sensor.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"
#include "multi_sensor_robot.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using test::loadErrors;
using test::loadWarnings;
using test::multiSensorRobot;
using test::multiSensorUrdf;
using test::parseExpecting;
using test::pluginNamed;
using test::withoutPluginTags;
using test::withSensorPluginTags;

using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsSupersetOf;

// Where the rangers sit on the robot (base_footprint frame) [m].
constexpr double kRangerAhead = 0.22;
constexpr double kRangerHeight = 0.15;
constexpr double kSonarLeft = -0.05;

/// The first range a ranger of a robot spawned at `pose` in the test room reads.
RangeSample firstRange(const std::string& sensor, const SpawnPose& pose, uint64_t seed = 0) {
  Simulation simulation(test::shippedWorld("test_room.world"), {.seed = seed});
  Robot& robot = simulation.spawn("robot", multiSensorRobot(), pose);
  RangeSensor& ranger = pluginNamed<RangeSensor>(robot, sensor);
  test::stepUntil(simulation, [&] { return ranger.sampleCount() > 0; }, 1.0, "a range");
  return ranger.sample();
}

/// The nearest hit of rays from `origin` along `directions` (yaw 0) on test_room.world's east wall (x = 3),
/// north wall (y = 2) and floor (z = 0).
double nearestInTheRoomsNorthEastCorner(const Eigen::Vector3d& origin,
                                        const std::vector<Eigen::Vector3f>& directions) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3f& direction : directions) {
    const Eigen::Vector3d d = direction.cast<double>();
    if (d.x() > 0) nearest = std::min(nearest, (3.0 - origin.x()) / d.x());
    if (d.y() > 0) nearest = std::min(nearest, (2.0 - origin.y()) / d.y());
    if (d.z() < 0) nearest = std::min(nearest, -origin.z() / d.z());
  }
  return nearest;
}

TEST(Range, FacingTheEastWallReadsItsDistance) {
  for (double x : {-0.5, 0.7, 1.9}) {
    const RangeSample range = firstRange("ir", {.x = x, .y = 0.3});
    EXPECT_NEAR(range.range, 3.0 - (x + kRangerAhead), 1e-3) << "robot at x = " << x;
    EXPECT_EQ(range.frame_id, "ir_link");
    EXPECT_TRUE(range.infrared);
    EXPECT_DOUBLE_EQ(range.field_of_view, 0.01);
    EXPECT_DOUBLE_EQ(range.min_range, 0.02);
    EXPECT_DOUBLE_EQ(range.max_range, 4.0);
  }
}

TEST(Range, NothingWithinRangeReadsTheMaximum) {
  // 4.72 m to the east wall, beyond the 4 m maximum.
  const RangeSample range = firstRange("ir", {.x = -1.94});
  EXPECT_EQ(range.range, 4.0);
}

TEST(Range, ANarrowBeamAndAWideConeReadTheNearestHitOfTheirRays) {
  // Near the north-east corner: 1 m from the east wall, 0.3 m from the north wall for the ultrasound ranger.
  const SpawnPose pose{.x = 2.0 - kRangerAhead, .y = 1.7 - kSonarLeft};
  const RangeSample ir = firstRange("ir", pose);
  const RangeSample sonar = firstRange("sonar", pose);
  EXPECT_NEAR(ir.range, 1.0, 1e-3) << "the beam sees only the east wall";
  EXPECT_FALSE(sonar.infrared);
  EXPECT_DOUBLE_EQ(sonar.field_of_view, 1.0);
  // The cone's leftmost rays meet the north wall first: 0.3 / sin(0.5) = 0.626 m.
  RayLidarConfig cone;
  cone.samples = 5;
  cone.min_angle = -0.5;
  cone.max_angle = 0.5;
  cone.min_elevation = -0.05;
  cone.max_elevation = 0.05;
  const double expected =
      nearestInTheRoomsNorthEastCorner({2.0, 1.7, kRangerHeight}, rayDirections(cone, /*channels=*/3));
  EXPECT_NEAR(expected, 0.3 / std::sin(0.5), 1e-6);
  EXPECT_NEAR(sonar.range, expected, 1e-3);
}

TEST(Range, NoiseIsSeededAndCentredOnTheTruth) {
  const std::string urdf = withSensorPluginTags(multiSensorUrdf(), "ir", {{"gaussianNoise", "0.01"}});
  const auto readings = [&](uint64_t seed) {
    Simulation simulation(test::shippedWorld("test_room.world"), {.seed = seed});
    Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "noisy"), {.x = 0.78});
    RangeSensor& ir = pluginNamed<RangeSensor>(robot, "ir");
    std::vector<double> ranges;
    while (ranges.size() < 200) {
      const uint64_t count = ir.sampleCount();
      simulation.step();
      if (ir.sampleCount() != count) ranges.push_back(ir.sample().range);
    }
    return ranges;
  };
  const std::vector<double> first = readings(7);
  EXPECT_EQ(first, readings(7)) << "the same seed gives the same noise";
  EXPECT_NE(first, readings(8));
  double mean = 0, square = 0;
  for (double range : first) mean += range / first.size();
  for (double range : first) square += (range - mean) * (range - mean) / (first.size() - 1);
  EXPECT_NEAR(mean, 2.0, 3 * 0.01 / std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(square), 0.01, 0.002);
}

TEST(Range, LoadMessages) {
  const std::string noisy_rays = test::editUrdf(multiSensorUrdf(), [](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      auto* sensor = gazebo->FirstChildElement("sensor");
      if (!sensor || std::string("ir") != sensor->Attribute("name")) continue;
      auto* noise = sensor->FirstChildElement("ray")->InsertNewChildElement("noise");
      noise->InsertNewChildElement("type")->SetText("gaussian");
      noise->InsertNewChildElement("stddev")->SetText("0.01");
    }
  });
  const std::string urdf = withSensorPluginTags(noisy_rays, "sonar", {{"radiation", "sonic"}});
  EXPECT_THAT(loadWarnings(urdf),
              IsSupersetOf({HasSubstr("sensor [ir] on link [ir_link] <ray><noise> does not reach "
                                      "libgazebo_ros_range.so's range (Gazebo's plugin reads the rays before the "
                                      "sensor's noise): ignored; use the plugin's <gaussianNoise>"),
                            HasSubstr("<radiation> must be ultrasound or infrared, not [sonic]: infrared is used, "
                                      "as Gazebo does")}));
  // Gazebo stamps the ranges with a frameName that names no link: a warning.
  EXPECT_THAT(loadWarnings(withSensorPluginTags(multiSensorUrdf(), "ir", {{"frameName", "ir_lnk"}})),
              Contains(HasSubstr("<frameName> [ir_lnk] is not a link of the robot (did you mean [ir_link]?): "
                                 "messages carry it as their frame_id all the same")));
}

// hector's IMU.

constexpr double kGravity = 9.81;
const std::string kImuPlugin = "libhector_gazebo_ros_imu.so";

/// The multi-sensor robot's IMU with every error model off but the tags in `tags`.
std::string idealImu(const test::Tags& tags = {}) {
  test::Tags all = {{"accelDrift", "0 0 0"}, {"accelGaussianNoise", "0 0 0"}, {"rateDrift", "0 0 0"},
                    {"rateGaussianNoise", "0 0 0"}, {"yawDrift", "0"}, {"yawGaussianNoise", "0"}};
  all.insert(all.end(), tags.begin(), tags.end());
  return test::withPluginTags(multiSensorUrdf(), kImuPlugin, all);
}

/// The samples of `imu` over `seconds` of sim time.
std::vector<ImuSample> imuSamples(Simulation& simulation, const HectorImu& imu, double seconds) {
  std::vector<ImuSample> samples;
  const double end = simulation.time() + seconds;
  while (simulation.time() < end - 1e-9) {
    const uint64_t count = imu.sampleCount();
    simulation.step();
    if (imu.sampleCount() != count) samples.push_back(imu.sample());
  }
  return samples;
}

TEST(HectorImu, AtRestReadsGravityUpAndNoRotationWithinItsNoise) {
  Simulation simulation(test::shippedWorld("empty.world"), {.seed = 3});
  Robot& robot = simulation.spawn("robot", multiSensorRobot(), {.x = 1, .yaw = 0.7});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 500; ++i) simulation.step();  // settled
  const std::vector<ImuSample> samples = imuSamples(simulation, imu, 4.0);
  ASSERT_EQ(samples.size(), 200u) << "50 Hz";
  Eigen::Vector3d accel = Eigen::Vector3d::Zero(), rate = Eigen::Vector3d::Zero();
  for (const auto& sample : samples) {
    accel += sample.linear_acceleration / samples.size();
    rate += sample.angular_velocity / samples.size();
  }
  // The drift starts at N(0, 0.005^2) per axis: 4 sigma of it, and of the white noise's mean.
  const double bound = 4 * 0.005 + 4 * 0.005 / std::sqrt(200.0);
  EXPECT_NEAR(accel.x(), 0, bound);
  EXPECT_NEAR(accel.y(), 0, bound);
  EXPECT_NEAR(accel.z(), kGravity, bound);
  EXPECT_LT(rate.norm(), 2 * bound);
  EXPECT_GT((samples[0].angular_velocity - samples[1].angular_velocity).norm(), 0) << "the noise is on";
  const ImuSample& last = samples.back();
  EXPECT_EQ(last.frame_id, "imu_link");
  EXPECT_DOUBLE_EQ(last.angular_velocity_variance.x(), 0.005 * 0.005);
  EXPECT_DOUBLE_EQ(last.linear_acceleration_variance.z(), 0.005 * 0.005);
  EXPECT_NEAR(last.orientation_variance.x(), 0.005 * 0.005 / (kGravity * kGravity), 1e-15);
  EXPECT_DOUBLE_EQ(last.orientation_variance.z(), 0.005 * 0.005);
}

TEST(HectorImu, WithoutErrorsMatchesTheGroundTruth) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", parseExpecting(idealImu(), "ideal"), {.x = 1, .yaw = 0.7});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 500; ++i) simulation.step();
  for (const ImuSample& sample : imuSamples(simulation, imu, 1.0)) {
    const Eigen::Quaterniond truth(robot.body().linkPose("imu_link").linear());
    EXPECT_LT(sample.orientation.angularDistance(truth), 1e-9);
    EXPECT_LT((sample.linear_acceleration - Eigen::Vector3d(0, 0, kGravity)).norm(), 1e-3);
    EXPECT_LT(sample.angular_velocity.norm(), 1e-3);
  }
  EXPECT_NEAR(Eigen::AngleAxisd(imu.sample().orientation).angle(), 0.7, 1e-3) << "yaw 0.7 at spawn";
}

TEST(HectorImu, OffsetsShowInTheReadingAndTheBiasTopic) {
  Simulation simulation(test::shippedWorld("empty.world"));
  const std::string urdf = idealImu({{"rateOffset", "0.1 0 0"}, {"accelOffset", "0 0.2 0"}});
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "offsets"), {});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 500; ++i) simulation.step();
  EXPECT_NEAR(imu.sample().angular_velocity.x(), 0.1, 1e-3);
  EXPECT_NEAR(imu.sample().linear_acceleration.y(), 0.2, 1e-3);
  EXPECT_TRUE(imu.bias().angular_velocity.isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_TRUE(imu.bias().linear_acceleration.isApprox(Eigen::Vector3d(0, 0.2, 0)));
  // The accelerometer's bias tilts the orientation as hector's pseudo-AHRS does: 0.2 m/s^2 to the left rolls
  // it by about 0.2 / g.
  EXPECT_NEAR(Eigen::AngleAxisd(imu.bias().orientation).angle(), 0.2 / kGravity, 1e-4);
}

TEST(HectorImu, CalibrateZeroesTheRateDrift) {
  Simulation simulation(test::shippedWorld("empty.world"), {.seed = 5});
  const std::string urdf = idealImu({{"rateDrift", "0.1 0.1 0.1"}});
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "drift"), {});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 100; ++i) simulation.step();
  EXPECT_GT(imu.bias().angular_velocity.norm(), 0.01) << "drawn from N(0, 0.1^2) per axis";
  const auto& ports = imu.ports().services;
  ASSERT_EQ(ports.size(), 1u);
  EXPECT_EQ(ports[0].name, "imu/data/calibrate");
  EmptyRequest::Reply reply;
  EXPECT_EQ(std::get<ServiceHandler<EmptyRequest>>(ports[0].handler)(EmptyRequest{}, reply), "");
  simulation.step();
  for (int i = 0; i < 20; ++i) simulation.step();
  EXPECT_LT(imu.bias().angular_velocity.norm(), 1e-3) << "the drift restarts from zero";
}

TEST(HectorImu, TheSameSeedGivesTheSameReadings) {
  const auto run = [](uint64_t seed) {
    Simulation simulation(test::shippedWorld("empty.world"), {.seed = seed});
    Robot& robot = simulation.spawn("robot", multiSensorRobot(), {});
    std::vector<double> readings;
    for (const ImuSample& sample : imuSamples(simulation, *test::pluginsOf<HectorImu>(robot).at(0), 0.5)) {
      readings.push_back(sample.linear_acceleration.x());
      readings.push_back(sample.orientation.z());
    }
    simulation.resetSimulation();
    const ImuSample after_reset = imuSamples(simulation, *test::pluginsOf<HectorImu>(robot).at(0), 0.5).back();
    EXPECT_EQ(after_reset.linear_acceleration.x(), readings[readings.size() - 2])
        << "a reset replays the run";
    return readings;
  };
  EXPECT_EQ(run(11), run(11));
  EXPECT_NE(run(11), run(12));
}

TEST(HectorImu, LoadMessages) {
  const std::string husky_style = test::withPluginTags(
      idealImu(), kImuPlugin, {{"headingDrift", "0.01"}, {"headingGaussianNoise", "0.02"}});
  const std::vector<std::string> warnings = loadWarnings(husky_style);
  EXPECT_THAT(warnings, Contains(HasSubstr("<headingDrift> is hector's old name of <yawDrift>, which today's "
                                           "hector ignores: ignored, since <yawDrift> is given")));
  const std::string without_yaw =
      withoutPluginTags(husky_style, kImuPlugin, {"yawDrift", "yawGaussianNoise"});
  EXPECT_THAT(loadWarnings(without_yaw),
              Contains(HasSubstr("<headingGaussianNoise> is hector's old name of <yawGaussianNoise>, which "
                                 "today's hector ignores: read as <yawGaussianNoise>")));
  const ModelSpec model = parseModel(without_yaw, "robot", PackageResolver::fromEnvironment());
  for (const auto& plugin : model.plugins) {
    if (const auto* config = plugin.configAs<HectorImuConfig>()) {
      EXPECT_DOUBLE_EQ(config->yaw.drift.x(), 0.01);
      EXPECT_DOUBLE_EQ(config->yaw.gaussian_noise.x(), 0.02);
    }
  }
  EXPECT_THAT(warnings, Contains(HasSubstr("hector's [imu/data/set_accel_bias] and [imu/data/set_rate_bias] "
                                           "services and its dynamic_reconfigure servers need hector's own "
                                           "types, which Debian lacks: left out")));
  const std::string bad =
      test::withPluginTags(idealImu(), kImuPlugin, {{"accelDrift", "0.1 0.1"}, {"bodyName", "imu_lnk"}});
  EXPECT_THAT(loadErrors(bad),
              ElementsAre(HasSubstr("<accelDrift> must be three numbers (x y z), not [0.1 0.1]")));
  EXPECT_THAT(
      loadWarnings(test::withPluginTags(idealImu(), kImuPlugin, {{"bodyName", "imu_lnk"}})),
      Contains(HasSubstr("<bodyName> [imu_lnk] is not a link of the robot (did you mean [imu_link]?): "
                         "messages carry it as their frame_id all the same, as Gazebo's do; link "
                         "[base_footprint] is measured instead")));
}

// hector's GPS.

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
  test::stepUntil(simulation, [&] { return gps.fixCount() > 0; }, 1.0, "a fix");
  return gps.fix();
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
      const uint64_t count = gps.fixCount();
      simulation.step();
      if (gps.fixCount() != count) latitudes.push_back(gps.fix().latitude);
    }
    EXPECT_DOUBLE_EQ(gps.fix().position_covariance[0], 0.0001 * 0.0001);
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

// Bumpers.

TEST(GazeboNames, LumpedCollisionsAreNamedAsSdformatNamesThem) {
  const ModelSpec robot = multiSensorRobot();
  EXPECT_EQ(gazeboLink(robot, "bumper_link"), "base_footprint");
  std::vector<std::string> names;
  for (const GazeboCollision& collision : gazeboCollisions(robot)) {
    EXPECT_EQ(collision.gazebo_link, "base_footprint");
    names.push_back(collision.name);
  }
  // base_link's box, then base_link's fixed children by joint name.
  EXPECT_EQ(names, (std::vector<std::string>{"base_footprint_fixed_joint_lump__base_link_collision",
                                             "base_footprint_fixed_joint_lump__bumper_link_collision_1",
                                             "base_footprint_fixed_joint_lump__caster_fl_collision_2",
                                             "base_footprint_fixed_joint_lump__caster_fr_collision_3",
                                             "base_footprint_fixed_joint_lump__caster_rl_collision_4",
                                             "base_footprint_fixed_joint_lump__caster_rr_collision_5"}));
  EXPECT_EQ(unlumpedCollisionNames(robot, "bumper_link"), std::vector<std::string>{"bumper_link_collision"});
}

TEST(GazeboNames, NamedMovingAndPreservedLinksKeepTheirOwn) {
  // A named collision on a link of its own, a second collision, and a fixed joint kept by preserveFixedJoint.
  std::string urdf = test::readFile(test::fixture("robots/two_wheeler.urdf"));
  urdf = test::replaceAfter(urdf, "<link name=\"left_wheel\">", "<collision>", "<collision name=\"tyre\">");
  urdf = test::replaceAfter(urdf, "<link name=\"base_link\">", "</link>",
                            "<collision><geometry><sphere radius=\"0.01\"/></geometry></collision></link>");
  urdf = test::replaceAfter(urdf, "</robot>", "</robot>",
                            "<gazebo reference=\"caster_joint\"><preserveFixedJoint>true</preserveFixedJoint>"
                            "</gazebo></robot>");
  const ModelSpec robot = test::parseQuietly(urdf, "two_wheeler");
  std::map<std::string, std::string> names;
  for (const GazeboCollision& collision : gazeboCollisions(robot)) {
    const std::string key = collision.link + "/" + std::to_string(collision.index);
    names[key] = collision.gazebo_link + "::" + collision.name;
  }
  EXPECT_EQ(names["base_link/0"], "base_footprint::base_footprint_fixed_joint_lump__base_link_collision");
  EXPECT_EQ(names["base_link/1"], "base_footprint::base_footprint_fixed_joint_lump__base_link_collision_1");
  EXPECT_EQ(names["caster/0"], "caster::caster_collision");
  // sdformat adds the lump prefix to a name that does not start with its link's, lumped or not.
  EXPECT_EQ(names["left_wheel/0"], "left_wheel::left_wheel_fixed_joint_lump__tyre_collision");
  EXPECT_EQ(names["right_wheel/0"], "right_wheel::right_wheel_collision");
}

constexpr char kBumperLink[] = R"(
  <joint name="bumper_joint" type="fixed">
    <parent link="base_link"/><child link="bumper_link"/><origin xyz="0.21 0 0.05"/>
  </joint>
  <link name="bumper_link">
    <collision><geometry><box size="0.02 0.3 0.06"/></geometry></collision>
  </link>
  <gazebo reference="bumper_link">
    <sensor type="contact" name="bumper">
      <update_rate>50</update_rate>
      <contact><collision>COLLISION</collision></contact>
      <plugin name="bumper_plugin" filename="libgazebo_ros_bumper.so">
        <bumperTopicName>bumper</bumperTopicName>
      </plugin>
    </sensor>
  </gazebo>
</robot>)";

/// two_wheeler.urdf with a diff drive, a bumper plate 0.22 m ahead of base_footprint and a contact sensor
/// watching `collision`.
std::string bumperCar(const std::string& collision, const std::string& wheel_model) {
  std::string bumper = kBumperLink;
  bumper.replace(bumper.find("COLLISION"), 9, collision);
  std::string urdf = test::readFile(test::fixture("robots/two_wheeler.urdf"));
  urdf.replace(urdf.find("</robot>"), 8, bumper);
  return test::withPlugin(urdf, "drive", "libgazebo_ros_diff_drive.so",
                          {{"leftJoint", "left_wheel_joint"},
                           {"rightJoint", "right_wheel_joint"},
                           {"wheelSeparation", "0.35"},
                           {"wheelDiameter", "0.1"},
                           {"wheelModel", wheel_model}});
}

constexpr char kLumpedBumper[] = "base_footprint_fixed_joint_lump__bumper_link_collision_1";

TEST(Bumper, ARobotDrivenIntoAWallReportsItsBumperTouchingItAndNothingBefore) {
  for (const std::string& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("test_room.world"));
    Robot& robot = simulation.spawn("car", test::parseQuietly(bumperCar(kLumpedBumper, wheel_model), "car"),
                                    {.x = 2.0});
    const Bumper& bumper = *test::pluginsOf<Bumper>(robot).at(0);
    WheeledDrive& drive = *test::pluginsOf<WheeledDrive>(robot).at(0);
    const auto front = [&] { return robot.body().linkPose("bumper_link").translation().x() + 0.01; };
    uint64_t seen = 0;
    int empty_updates = 0;
    while (front() < 3.0 - 1e-3) {
      ASSERT_LT(simulation.time(), 10.0) << "the car never reached the wall";
      drive.setCommand(0.3, 0, simulation.time());
      simulation.step();
      if (bumper.contactsCount() == seen) continue;
      seen = bumper.contactsCount();
      EXPECT_THAT(bumper.contacts().states, testing::IsEmpty())
          << "the plate is " << 3.0 - front() << " m off";
      ++empty_updates;
    }
    EXPECT_GT(empty_updates, 50) << "a bumper publishes every update, empty while nothing touches";
    ASSERT_TRUE(test::stepUntil(
        simulation, [&] { return !bumper.contacts().states.empty(); }, 1.0, "the bumper's contact"));
    for (int i = 0; i < 200; ++i) {
      drive.setCommand(0.3, 0, simulation.time());
      simulation.step();
    }
    const ContactsSample& contacts = bumper.contacts();
    EXPECT_EQ(contacts.frame_id, "world");
    ASSERT_EQ(contacts.states.size(), 1u) << "the wheels and the caster on the ground are other collisions";
    const ContactsSample::State& state = contacts.states[0];
    EXPECT_EQ(state.collision1, std::string("car::base_footprint::") + kLumpedBumper);
    EXPECT_EQ(state.collision2, "room::wall_east::collision");
    ASSERT_FALSE(state.positions.empty());
    for (size_t i = 0; i < state.positions.size(); ++i) {
      EXPECT_NEAR(state.positions[i].x(), 3.0, 0.005);
      EXPECT_LT((state.normals[i] - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-6);
    }
    EXPECT_LT(state.total_wrench.force.x(), -1.0) << "the wall pushes the car back";
    EXPECT_THAT(state.info, HasSubstr("my geom:car::base_footprint::" + std::string(kLumpedBumper)));
  }
}

TEST(Bumper, ACollisionNamedAsBeforeLumpingIsWatchedWithAWarning) {
  const std::string urdf = bumperCar("bumper_link_collision", "contact");
  EXPECT_THAT(loadWarnings(urdf),
              Contains(HasSubstr("<contact><collision> [bumper_link_collision] is the name of link "
                                 "[bumper_link]'s collision before Gazebo lumps that link into "
                                 "[base_footprint]; there it is [" +
                                 std::string(kLumpedBumper) + "], and Gazebo's bumper, finding no "
                                 "[bumper_link_collision], reports nothing: bullet_sim watches [" +
                                 std::string(kLumpedBumper) + "]")));
  const ModelSpec model = parseModel(urdf, "car", PackageResolver::fromEnvironment());
  for (const auto& plugin : model.plugins) {
    if (const auto* bumper = plugin.configAs<BumperConfig>()) {
      ASSERT_EQ(bumper->collisions.size(), 1u);
      EXPECT_EQ(bumper->collisions[0].name, kLumpedBumper);
    }
  }
}

TEST(Bumper, ACollisionNamingNothingIsAWarningWithASuggestion) {
  EXPECT_THAT(loadWarnings(bumperCar("base_footprint_fixed_joint_lump__bumper_link_collision_2", "contact")),
              Contains(HasSubstr("<contact><collision> "
                                 "[base_footprint_fixed_joint_lump__bumper_link_collision_2] is no collision "
                                 "of link [base_footprint] as Gazebo names them (did you mean [" +
                                 std::string(kLumpedBumper) + "]?): it reports nothing, as in Gazebo")));
}

}  // namespace
}  // namespace bullet_sim
