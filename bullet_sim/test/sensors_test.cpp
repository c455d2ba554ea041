// Gazebo's rangers, hector's IMU and GPS, and bumpers against analytic truth, on the multi-sensor test robot
// (test/fixtures/robots/multi_sensor_robot.urdf.xacro). Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bullet_sim/plugins/range_sensor.h"
#include "bullet_sim/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

const std::string kFixture = "test/fixtures/robots/multi_sensor_robot.urdf.xacro";

/// `urdf` with the tags of the plugin of sensor `sensor` set (or added).
std::string withSensorPluginTags(const std::string& urdf, const std::string& sensor, const test::Tags& tags) {
  return test::editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      for (auto* element = gazebo->FirstChildElement("sensor"); element;
           element = element->NextSiblingElement("sensor")) {
        if (sensor != element->Attribute("name")) continue;
        auto* plugin = element->FirstChildElement("plugin");
        for (const auto& [tag, text] : tags) {
          auto* child = plugin->FirstChildElement(tag.c_str());
          (child ? child : plugin->InsertNewChildElement(tag.c_str()))->SetText(text.c_str());
        }
        return;
      }
    }
    throw std::runtime_error("no sensor [" + sensor + "]");
  });
}

/// The multi-sensor robot, with planar move or force-based move.
ModelSpec multiSensorRobot(const std::string& drive = "planar") {
  return test::parseQuietly(test::expandXacro("bullet_sim", kFixture, {"drive:=" + drive}),
                            "multi_sensor_robot");
}

template <class T>
T& pluginNamed(const Robot& robot, const std::string& name) {
  for (T* plugin : robot.pluginsOf<T>()) {
    if (plugin->name() == name) return *plugin;
  }
  throw std::runtime_error("no plugin [" + name + "]");
}

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
  const std::string urdf = withSensorPluginTags(test::expandXacro("bullet_sim", kFixture, {"drive:=planar"}),
                                                "ir", {{"gaussianNoise", "0.01"}});
  const auto readings = [&](uint64_t seed) {
    Simulation simulation(test::shippedWorld("test_room.world"), {.seed = seed});
    Robot& robot = simulation.spawn("robot", test::parseQuietly(urdf, "noisy"), {.x = 0.78});
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

}  // namespace
}  // namespace bullet_sim
