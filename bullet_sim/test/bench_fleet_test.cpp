// bench --robots' fleets, run in-process: every robot of a small fleet starts on its own place of the grid
// and drives its own circle. Timings are bench's to print, never asserted here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "bench/bench_fleet.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

/// The wheelchair's drive ramps each wheel's speed at a = 1.8 m/s^2 (its <wheelAcceleration>): from rest its
/// axle lags the unicycle by v^2 / (2 a) = 2.5 cm at 0.3 m/s, and its heading by w v / a = 0.05 rad (the
/// inner wheel reaches its speed first; until then both roll alike).
constexpr double kWheelAcceleration = 1.8;  ///< [m/s^2]
constexpr double kRampLag = 0.05;           ///< [m]: twice the axle's lag
constexpr double kYawTolerance = 0.01;      ///< [rad] of the heading from the ramped unicycle's
constexpr double kGridTolerance = 0.01;     ///< [m] of a settled robot from its place on the grid

TEST(BenchFleet, EveryRobotDrivesItsOwnCircleFromItsPlaceOnTheGrid) {
  FleetOptions options;
  options.urdf = test::expandXacro("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro");
  options.source = "smartwheelchair_model.urdf.xacro";
  options.duration = 4;
  const int count = 3;
  std::vector<std::string> warnings;
  const FleetRun run = driveFleet(test::shippedWorld("empty.world"), count, options, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  ASSERT_EQ(run.settled.size(), count);
  ASSERT_EQ(run.end.size(), count);

  // Three robots on a 2 x 2 grid: robot2 1.5 m along x from robot1, robot3 1.5 m along y; all face +x.
  const Planar& first = run.settled[0];
  EXPECT_NEAR(run.settled[1].x - first.x, options.spacing, kGridTolerance);
  EXPECT_NEAR(run.settled[1].y - first.y, 0, kGridTolerance);
  EXPECT_NEAR(run.settled[2].x - first.x, 0, kGridTolerance);
  EXPECT_NEAR(run.settled[2].y - first.y, options.spacing, kGridTolerance);

  // From rest at v and w, after t the axle has turned w t (less the ramp's lag) and lies on the chord
  // 2 v/w sin(w t / 2), along the start's yaw + w t / 2.
  const double turn = options.w * options.duration;
  const double ramped_turn = turn - options.w * options.v / kWheelAcceleration;
  const double chord = 2 * options.v / options.w * std::sin(turn / 2);
  for (int k = 0; k < count; ++k) {
    const Planar& start = run.settled[k];
    const Planar& end = run.end[k];
    SCOPED_TRACE("robot" + std::to_string(k + 1));
    EXPECT_NEAR(test::angleDifference(start.yaw, 0), 0, kYawTolerance);
    EXPECT_NEAR(std::hypot(end.x - start.x, end.y - start.y), chord, kRampLag);
    EXPECT_NEAR(test::angleDifference(end.yaw, start.yaw), ramped_turn, kYawTolerance);
    // The ramp's lag, seen from the start, turns the chord by up to its length over the chord's.
    EXPECT_NEAR(test::angleDifference(std::atan2(end.y - start.y, end.x - start.x), start.yaw), turn / 2,
                kRampLag / chord);
  }

  // Every robot's lidar scanned at its own rate (the wheelchair's 5.5 Hz) all along the drive.
  const double lidar_rate = 5.5;  // [Hz] smartwheelchair_model.gazebo.xacro's <update_rate>
  EXPECT_NEAR(static_cast<double>(run.lidar_scans), count * lidar_rate * options.duration, count);
}

}  // namespace
}  // namespace bullet_sim
