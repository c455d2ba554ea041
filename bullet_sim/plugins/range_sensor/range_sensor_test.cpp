// Gazebo's rangers against analytic truth, on the multi-sensor test robot
// (test/fixtures/robots/multi_sensor_robot.urdf.xacro) in test_room.world. Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "plugins/range_sensor/range_sensor.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using test::loadWarnings;
using test::multiSensorRobot;
using test::multiSensorUrdf;
using test::parseExpecting;
using test::pluginNamed;
using test::withSensorPluginTags;

using ::testing::Contains;
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
  test::stepUntil(simulation, [&] { return test::countOf<RangeSample>(ranger) > 0; }, 1.0, "a range");
  return test::latestOf<RangeSample>(ranger);
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
      const uint64_t count = test::countOf<RangeSample>(ir);
      simulation.step();
      if (test::countOf<RangeSample>(ir) != count) ranges.push_back(test::latestOf<RangeSample>(ir).range);
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

/// The multi-sensor robot with a <ray><noise> of standard deviation `stddev` on its [ir] ranger.
std::string withNoisyRays(const std::string& stddev) {
  return test::editUrdf(multiSensorUrdf(), [&](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      auto* sensor = gazebo->FirstChildElement("sensor");
      if (!sensor || std::string("ir") != sensor->Attribute("name")) continue;
      auto* noise = sensor->FirstChildElement("ray")->InsertNewChildElement("noise");
      noise->InsertNewChildElement("type")->SetText("gaussian");
      noise->InsertNewChildElement("stddev")->SetText(stddev.c_str());
    }
  });
}

TEST(Range, ANegativeRayNoiseGetsOneWarningThatNamesIt) {
  // The sensor's noise never reaches the plugin's ranges, so its sign matters to nothing: one warning.
  std::vector<std::string> noise_warnings;
  for (const std::string& warning : loadWarnings(withNoisyRays("-0.01"))) {
    if (warning.find("<noise>") != std::string::npos) noise_warnings.push_back(warning);
  }
  EXPECT_THAT(noise_warnings,
              testing::ElementsAre(HasSubstr("sensor [ir] on link [ir_link] <ray><noise> (stddev -0.01, "
                                             "mean 0) does not reach libgazebo_ros_range.so's range")));
}

TEST(Range, LoadMessages) {
  const std::string urdf = withSensorPluginTags(withNoisyRays("0.01"), "sonar", {{"radiation", "sonic"}});
  EXPECT_THAT(
      loadWarnings(urdf),
      IsSupersetOf({HasSubstr("sensor [ir] on link [ir_link] <ray><noise> (stddev 0.01, mean 0) does not "
                              "reach libgazebo_ros_range.so's range (Gazebo's plugin reads the rays before "
                              "the sensor's noise): ignored; use the plugin's <gaussianNoise>"),
                    HasSubstr("<radiation> must be ultrasound or infrared, not [sonic]: infrared is used, "
                              "as Gazebo does")}));
  // Gazebo stamps the ranges with a frameName that names no link: a warning.
  EXPECT_THAT(loadWarnings(withSensorPluginTags(multiSensorUrdf(), "ir", {{"frameName", "ir_lnk"}})),
              Contains(HasSubstr("<frameName> [ir_lnk] is not a link of the robot (did you mean [ir_link]?): "
                                 "messages carry it as their frame_id all the same")));
}

}  // namespace
}  // namespace bullet_sim
