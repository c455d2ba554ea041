// Issue 28, wall and edge strikes of the shipped robots (the wheelchair, the smartcar, the Yahboom car, the
// Tianracer and the rover, through ros_control), on both wheel models at 1 and 10 ms, against bounds computed
// from their own mass, inertia and geometry (tools/strike_matrix.h). `bench --strikes` runs the whole matrix.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "contact_support.h"

namespace bullet_sim {
namespace {

class ShippedStrike : public ::testing::TestWithParam<test::StrikeCase> {};

TEST_P(ShippedStrike, StaysWithinItsBounds) { test::expectWithinBounds(GetParam().robot, GetParam().cell); }

INSTANTIATE_TEST_SUITE_P(Matrix, ShippedStrike, ::testing::ValuesIn(test::representativeCells(test::shippedRobots())),
                         test::caseName);

// The Yahboom car's front wheels reach 1 mm past its body and all four are driven, friction-limited: the
// wall's friction on a spinning front wheel, mu times its share of the push (mu m g / 2), is twice the load
// on that wheel, so the wheel climbs the wall, on either wheel model, as it would in Gazebo.
TEST(ShippedStrike, TheYahboomCarsDrivenFrontWheelsClimbTheWall) {
  const StrikeRobot yahboom = test::shippedRobots()[2];
  for (const std::string model : test::kWheelModels) {
    SCOPED_TRACE(model);
    const StrikeOutcome outcome = runStrike(yahboom, {model, 0.001, 0.5}, test::emptyWorld());
    EXPECT_TRUE(outcome.bounds.wheel_first);
    EXPECT_GT(outcome.bounds.climb_ratio, 1.5);
    EXPECT_GT(outcome.max_tilt, 0.1) << "it climbs";
    EXPECT_TRUE(outcome.passed()) << test::describe(outcome);
  }
}

}  // namespace
}  // namespace bullet_sim
