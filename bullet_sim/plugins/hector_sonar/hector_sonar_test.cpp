// hector's sonar against analytic truth, on the multi-sensor test robot with its ultrasound ranger's plugin
// swapped for libhector_gazebo_ros_sonar.so, in test_room.world (east wall at x = 3). Stepped in-process.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bullet_sim/simulation/simulation.h"
#include "plugins/hector_sonar/hector_sonar.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

constexpr double kSonarAhead = 0.22;  // [m] of the sonar ahead of base_footprint

/// The multi-sensor robot whose "sonar" sensor has hector's plugin with `tags`, and its range up to `max`
/// [m].
ModelSpec robotWithHectorSonar(const test::Tags& tags, const std::string& max) {
  const std::string urdf = test::editUrdf(test::multiSensorUrdf(), [&](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      auto* sensor = gazebo->FirstChildElement("sensor");
      if (!sensor || std::string(sensor->Attribute("name")) != "sonar") continue;
      sensor->FirstChildElement("ray")->FirstChildElement("range")->FirstChildElement("max")->SetText(
          max.c_str());
      auto* plugin = sensor->FirstChildElement("plugin");
      plugin->DeleteChildren();
      plugin->SetAttribute("filename", "libhector_gazebo_ros_sonar.so");
      for (const auto& [tag, text] : tags) plugin->InsertNewChildElement(tag.c_str())->SetText(text.c_str());
    }
  });
  return test::parseExpecting(urdf, "hector_sonar");
}

/// The ranges the sonar (reaching `max` [m]) of a robot at `x` (facing the east wall) publishes within
/// `seconds`.
std::vector<RangeSample> rangesAt(double x, const test::Tags& tags, double seconds,
                                  const std::string& max = "4.0") {
  Simulation simulation(test::shippedWorld("test_room.world"), {.seed = 7});
  Robot& robot = simulation.spawn("robot", robotWithHectorSonar(tags, max), {.x = x, .y = 0.3});
  const HectorSonar& sonar = test::pluginNamed<HectorSonar>(robot, "sonar");
  std::vector<RangeSample> ranges;
  const auto steps = std::lround(seconds / simulation.stepSize());
  for (long i = 0; i < steps; ++i) {
    simulation.step();
    if (test::countOf<RangeSample>(sonar) > ranges.size())
      ranges.push_back(test::latestOf<RangeSample>(sonar));
  }
  return ranges;
}

TEST(HectorSonar, ReadsTheWallAtHectorsRateWithHectorsFieldOfView) {
  const std::vector<RangeSample> ranges =
      rangesAt(1.0, {{"topicName", "sonar"}, {"frameId", "sonar_link"}}, 1.0);
  EXPECT_EQ(ranges.size(), 10u) << "hector's 10 Hz";
  ASSERT_FALSE(ranges.empty());
  const RangeSample& range = ranges.back();
  EXPECT_NEAR(range.range, 3.0 - (1.0 + kSonarAhead), 1e-3);
  EXPECT_EQ(range.frame_id, "sonar_link");
  EXPECT_FALSE(range.infrared) << "always ultrasound";
  EXPECT_DOUBLE_EQ(range.field_of_view, 0.1) << "the narrower span: 0.1 rad up and down, not 1 rad across";
  EXPECT_DOUBLE_EQ(range.min_range, 0.02);
  EXPECT_DOUBLE_EQ(range.max_range, 4.0);
}

TEST(HectorSonar, OffsetAndWhiteNoiseAreHectorsAndNothingInRangeReadsTheMaximum) {
  // Every step (updateRate 0) for 1 s: 1000 ranges of the wall 1.78 m ahead, + 0.1 m, with 0.05 m noise.
  const std::vector<RangeSample> ranges =
      rangesAt(1.0, {{"updateRate", "0"}, {"offset", "0.1"}, {"gaussianNoise", "0.05"}}, 1.0);
  ASSERT_GE(ranges.size(), 999u);
  double sum = 0, squares = 0;
  for (const RangeSample& range : ranges) sum += range.range;
  const double mean = sum / ranges.size();
  for (const RangeSample& range : ranges) squares += (range.range - mean) * (range.range - mean);
  const double stddev = std::sqrt(squares / (ranges.size() - 1));
  EXPECT_NEAR(mean, 3.0 - (1.0 + kSonarAhead) + 0.1, 4 * 0.05 / std::sqrt(ranges.size()));
  EXPECT_NEAR(stddev, 0.05, 0.005);
  EXPECT_EQ(ranges.front().frame_id, "sonar_link") << "hector's default, its '/' dropped";

  // 4.72 m to the east wall and 3 m to where the lowest rays meet the floor, beyond a 2 m maximum: the
  // maximum, with no noise.
  for (const RangeSample& range : rangesAt(-1.94, {{"gaussianNoise", "0.05"}}, 0.5, "2.0")) {
    EXPECT_EQ(range.range, 2.0);
  }
}

}  // namespace
}  // namespace bullet_sim
