// Issue 28, wall and edge strikes of the shipped robots (the wheelchair, the smartcar, the Yahboom car, the
// Tianracer and the rover, through ros_control), on both wheel models at 1 and 10 ms, against bounds computed
// from their own mass, inertia and geometry (tools/strike_matrix.h). `bench --strikes` runs the whole matrix.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "contact_support.h"

namespace bullet_sim {
namespace {

class ShippedStrike : public ::testing::TestWithParam<test::StrikeCase> {};

TEST_P(ShippedStrike, StaysWithinItsBounds) { test::expectWithinBounds(GetParam().robot, GetParam().cell); }

INSTANTIATE_TEST_SUITE_P(Matrix, ShippedStrike,
                         ::testing::ValuesIn(test::representativeCells(test::shippedRobots())),
                         test::caseName);

// The Yahboom car's front wheels reach 1 mm past its body and all four are driven, friction-limited: the
// wall's friction on a spinning front wheel, mu times its share of the push (mu m g / 2), is twice the load
// on that wheel, so the wheel climbs the wall, on either wheel model, as it would in Gazebo.
TEST(ShippedStrike, TheYahboomCarsDrivenFrontWheelsClimbTheWall) {
  const StrikeRobot yahboom = test::shippedRobots()[2];
  for (const std::string& model : test::kWheelModels) {
    SCOPED_TRACE(model);
    const StrikeOutcome outcome = runStrike(yahboom, {model, 0.001, 0.5}, test::emptyWorld());
    EXPECT_TRUE(outcome.bounds.wheel_first);
    EXPECT_GT(outcome.bounds.climb_ratio, 1.5);
    EXPECT_GT(outcome.max_tilt, 0.1) << "it climbs";
    EXPECT_TRUE(outcome.passed()) << test::describe(outcome);
  }
}

// At 2 m/s into a door's edge, on `contact` at 10 ms, the Yahboom car's front wheel climbs the post (climb
// ratio about 4), the car turns over and falls back onto its roof. Its root's path is longer than the
// command's by part of that fall, which gravity gives it: the matrix allows the root's rise for it where
// climbing is physical.
TEST(ShippedStrike, TheYahboomCarsFallAfterItClimbsIsNotAFling) {
  const StrikeRobot yahboom = test::shippedRobots()[2];
  const StrikeOutcome outcome =
      runStrike(yahboom, {"contact", 0.01, 2.0, 0.0, StrikeTarget::kDoorEdge}, test::emptyWorld());
  EXPECT_TRUE(outcome.bounds.climbs());
  EXPECT_GT(outcome.max_tilt, M_PI / 2) << "it climbs and turns over";
  EXPECT_GT(outcome.root_rise, 0.05);
  EXPECT_LE(outcome.path, outcome.command_path + 0.05 + outcome.root_rise);
  EXPECT_TRUE(outcome.passed()) << test::describe(outcome);
}

// The wheelchair struck at 60 degrees at 2 m/s meets the wall with its left drive wheel first. Its motor's
// 30 N m over the 0.284 m radius lets the wall's friction lift that wheel by at most 106 N, less than the
// 141 N on it (climb ratio 0.75): it stays on the ground and the chair slides along the wall, upright. (The
// raycast rim once took the wall's friction without the motor's limit, climbed, and rolled the chair onto its
// side: 1.4 to 1.9 rad.)
TEST(ShippedStrike, TheWheelchairStruckAtSixtyDegreesAtSpeedStaysUpright) {
  const StrikeRobot wheelchair = test::shippedRobots()[0];
  for (const double step : {0.001, 0.01}) {
    for (const StrikeTarget target : {StrikeTarget::kWall, StrikeTarget::kDoorEdge}) {
      const StrikeCell cell{"raycast", step, 2.0, M_PI / 3, target};
      SCOPED_TRACE(cellName(wheelchair, cell));
      const StrikeOutcome outcome = runStrike(wheelchair, cell, test::emptyWorld());
      EXPECT_TRUE(outcome.bounds.wheel_first);
      EXPECT_FALSE(outcome.bounds.tips());
      EXPECT_LT(outcome.bounds.climb_ratio, 0.8) << "the motor cannot carry the wheel up the wall";
      EXPECT_TRUE(outcome.reached);
      EXPECT_LT(outcome.max_tilt, 0.35) << "the matrix's bound at 2 m/s";
      EXPECT_TRUE(outcome.passed()) << test::describe(outcome);
    }
  }
}

}  // namespace
}  // namespace bullet_sim
