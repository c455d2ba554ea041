// Issue 28, wall and edge strikes: the look-alikes of common public robots (test/fixtures/contact/) driven
// into a flat wall, a door frame's edge and a 2 cm panel, on both wheel models at 1 and 10 ms, stay within
// bounds computed from their own mass, inertia and geometry (tools/strike_matrix.h): upright where the
// tipping bounds say upright, no leap, no tunnelling, no fling. `bench --strikes` runs the whole matrix.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "contact_support.h"

namespace bullet_sim {
namespace {

// light_skid_steer by hand: a 2 kg body (centre 0.08 m up, iyy 0.0203) on four 0.2 kg wheels (r 0.05 m,
// iyy 2.5e-4, axles 0.1 m ahead and behind): M = 2.8 kg, h = (2 * 0.08 + 0.8 * 0.05) / 2.8 = 0.0714 m, and
// about the lateral axis through the centre of mass I = 0.0203 + 2 (0.0086)^2 + 4 (2.5e-4 + 0.2 (0.1^2 +
// 0.0214^2)) = 0.0298 kg m^2. Its body reaches 2 cm past the wheels, so a wall meets the middle of its front
// face, z_c = 0.08 m, just above h: the impact turns it backwards about the rear axle, d = 0.1 m, with
// I_p = 0.0298 + 2.8 (0.1^2 + 0.0714^2) = 0.0721 kg m^2.
TEST(StrikeBounds, FollowTheFormulasForTheLightSkidSteerRobot) {
  for (const std::string& model : test::kWheelModels) {
    SCOPED_TRACE(model);
    const StrikeOutcome outcome =
        runStrike(test::lookAlike("light_skid_steer"), {model, 0.001, 0.5}, test::emptyWorld());
    const StrikeBounds& b = outcome.bounds;
    const double m = 2.8, h = 0.0714, z_c = 0.08, d = 0.1, i_p = 0.0721, g = 9.81;
    EXPECT_NEAR(b.mass, m, 1e-9);
    EXPECT_NEAR(b.com_height, h, 1e-3);
    EXPECT_NEAR(b.contact_height, z_c, 1e-3);
    EXPECT_NEAR(b.rear, d, 2e-3);
    EXPECT_NEAR(b.pitch_inertia, i_p, 0.02 * i_p);
    // omega0 = m v (z_c - h) / I_p about the rear axle; with z_c - h only 9 mm, from the bounds' own heights.
    const double omega = m * 0.5 * (b.contact_height - b.com_height) / b.pitch_inertia;
    EXPECT_NEAR(b.impact_energy, 0.5 * b.pitch_inertia * omega * omega, 1e-12);
    EXPECT_NEAR(b.barrier, m * g * (std::hypot(d, h) - h), 0.03 * m * g * (std::hypot(d, h) - h));
    EXPECT_FALSE(b.impact_tips);
    // Stall: all four wheels driven, friction-limited: F = mu m g = 27.5 N at z_c against m g d.
    EXPECT_NEAR(b.push, m * g, 1e-6);
    EXPECT_TRUE(b.rear_driven);
    EXPECT_FALSE(b.stall_tips) << b.push * b.contact_height << " N m against " << m * g * b.rear;
    EXPECT_FALSE(b.wheel_first);
    EXPECT_TRUE(outcome.passed()) << test::describe(outcome);
  }
}

class LookAlikeStrike : public ::testing::TestWithParam<test::StrikeCase> {};

TEST_P(LookAlikeStrike, StaysWithinItsBounds) {
  test::expectWithinBounds(GetParam().robot, GetParam().cell);
}

INSTANTIATE_TEST_SUITE_P(Matrix, LookAlikeStrike,
                         ::testing::ValuesIn(test::representativeCells(test::lookAlikes())),
                         test::caseName);

// The tall base's head meets the wall first, 1.3 m up, far above its centre of mass: were nothing else in the
// way, the impact at 2 m/s would throw it over backwards, and its wheels pushing on would rear it up. But its
// base reaches the wall 5 cm further on, after it has leant back by 0.05 rad, so it leans there.
TEST(StrikeBounds, ARobotWhoseBaseReachesTheWallLeansOnItInsteadOfTipping) {
  for (const std::string& model : test::kWheelModels) {
    SCOPED_TRACE(model);
    const StrikeOutcome outcome =
        runStrike(test::lookAlike("tall_base"), {model, 0.001, 2.0}, test::emptyWorld());
    const StrikeBounds& b = outcome.bounds;
    EXPECT_GT(b.contact_height, b.com_height + 0.8);
    EXPECT_GT(b.impact_energy, b.barrier) << "with room to turn, the impact would tip it";
    EXPECT_FALSE(b.tips()) << "its base meets the wall first";
    EXPECT_GT(outcome.max_tilt, 0.02) << "it leans back";
    EXPECT_TRUE(outcome.passed()) << test::describe(outcome);
  }
}

// The caster two-wheeler meets a door frame's edge square. Its centre of mass is 3 cm behind its axle: with
// springs alike it rested 4.2 mrad nose-up on `raycast`, met the post with its body's lower edge first and
// vaulted on it (0.44 rad at 2 m/s); and Bullet's box-box detector, which keeps only touching points, held
// its face at one edge on `contact` at 10 ms (0.108 rad at 0.5 m/s). The bounds say upright in all three.
TEST(StrikeBounds, ARobotMeetsADoorEdgeWithItsWholeFace) {
  const StrikeRobot robot = test::lookAlike("caster_two_wheeler");
  const StrikeCell cells[] = {{"raycast", 0.001, 2.0, 0, StrikeTarget::kDoorEdge},
                              {"raycast", 0.01, 2.0, 0, StrikeTarget::kDoorEdge},
                              {"contact", 0.01, 0.5, 0, StrikeTarget::kDoorEdge}};
  for (const StrikeCell& cell : cells) {
    SCOPED_TRACE(cellName(robot, cell));
    test::expectWithinBounds(robot, cell);
  }
}

}  // namespace
}  // namespace bullet_sim
