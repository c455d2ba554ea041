// The joint trajectory controller's mathematics against closed forms, without a world: the spline segments
// (positions, velocities and accelerations at the knots and between them), tolerance checking, the
// constraints' parameters, and how a new trajectory replaces the running one.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/common/diagnostics.h"
#include "plugins/ros_control/joint_trajectory.h"

namespace bullet_sim {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::SizeIs;

constexpr double kTight = 1e-12;

void expectMotion(const JointMotion& motion, double position, double velocity, double acceleration,
                  const std::string& where) {
  EXPECT_NEAR(motion.position, position, 1e-9) << where;
  EXPECT_NEAR(motion.velocity, velocity, 1e-9) << where;
  EXPECT_NEAR(motion.acceleration, acceleration, 1e-9) << where;
}

TEST(SplineSegment, PositionsAloneGiveALine) {
  const SplineSegment line(1.0, {1.0}, 3.0, {3.0});
  EXPECT_EQ(line.order(), SplineSegment::Order::kLinear);
  expectMotion(line.sample(1.0), 1.0, 1.0, 0, "start");
  expectMotion(line.sample(2.0), 2.0, 1.0, 0, "middle");
  expectMotion(line.sample(3.0), 3.0, 1.0, 0, "end");
  // Outside the segment it rests at its ends, as ros_controllers samples it.
  expectMotion(line.sample(0.5), 1.0, 0, 0, "before");
  expectMotion(line.sample(3.5), 3.0, 0, 0, "after");
}

TEST(SplineSegment, VelocitiesGiveTheCubicHermite) {
  // p(T/2) = (p0 + p1) / 2 + T (v0 - v1) / 8; p'' = 6 (p1 - p0) / T^2 - (4 v0 + 2 v1) / T at the start and
  // -6 (p1 - p0) / T^2 + (2 v0 + 4 v1) / T at the end.
  const double p0 = 1, v0 = 0.5, p1 = 3, v1 = -1, T = 2;
  const SplineSegment cubic(10, {p0, v0}, 10 + T, {p1, v1});
  EXPECT_EQ(cubic.order(), SplineSegment::Order::kCubic);
  expectMotion(cubic.sample(10), p0, v0, 6 * (p1 - p0) / (T * T) - (4 * v0 + 2 * v1) / T, "start");
  expectMotion(cubic.sample(10 + T), p1, v1, -6 * (p1 - p0) / (T * T) + (2 * v0 + 4 * v1) / T, "end");
  EXPECT_NEAR(cubic.sample(10 + T / 2).position, (p0 + p1) / 2 + T * (v0 - v1) / 8, kTight);
}

TEST(SplineSegment, AccelerationsGiveTheQuinticThroughAllSixConditions) {
  const SplineSegment quintic(0, {-0.4, 1.5, -2.0}, 1.5, {0.7, -0.3, 4.0});
  EXPECT_EQ(quintic.order(), SplineSegment::Order::kQuintic);
  expectMotion(quintic.sample(0), -0.4, 1.5, -2.0, "start");
  expectMotion(quintic.sample(1.5), 0.7, -0.3, 4.0, "end");
}

TEST(SplineSegment, RestToRestQuinticIsTheMinimumJerkProfile) {
  // p = p0 + d (10 s^3 - 15 s^4 + 6 s^5), s = t / T: at s = 1/2 the middle, at 15 d / (8 T), without
  // acceleration.
  const double d = 2.0, T = 4.0;
  const SplineSegment quintic(0, {1.0, 0.0, 0.0}, T, {1.0 + d, 0.0, 0.0});
  expectMotion(quintic.sample(T / 2), 1.0 + d / 2, 15 * d / (8 * T), 0, "middle");
  const double s = 0.25;
  EXPECT_NEAR(quintic.sample(s * T).position,
              1.0 + d * (10 * std::pow(s, 3) - 15 * std::pow(s, 4) + 6 * std::pow(s, 5)), kTight);
}

TEST(SplineSegment, TheLeastTheWaypointsShareIsUsed) {
  EXPECT_EQ(SplineSegment(0, {0, 1.0}, 1, {1}).order(), SplineSegment::Order::kLinear);
  EXPECT_EQ(SplineSegment(0, {0, 1.0, 2.0}, 1, {1, 0.0}).order(), SplineSegment::Order::kCubic);
  // Accelerations without velocities are not used.
  EXPECT_EQ(SplineSegment(0, {0, std::nullopt, 2.0}, 1, {1, std::nullopt, 0.0}).order(),
            SplineSegment::Order::kLinear);
}

TEST(SplineSegment, ZeroDurationHoldsAndBadFiguresAreRefused) {
  const SplineSegment hold(2, {0.3, 0.0, 0.0}, 2, {0.3, 0.0, 0.0});
  expectMotion(hold.sample(2), 0.3, 0, 0, "at");
  expectMotion(hold.sample(5), 0.3, 0, 0, "after");
  EXPECT_THROW(SplineSegment(2, {0}, 1, {1}), std::invalid_argument);
  EXPECT_THROW(SplineSegment(0, {NAN}, 1, {1}), std::invalid_argument);
  EXPECT_THROW(SplineSegment(0, {0, INFINITY}, 1, {1, 0.0}), std::invalid_argument);
}

TEST(Tolerances, ZeroIsNotEnforcedAndEachBoundIsItsOwn) {
  const JointMotion error{0.05, -0.2, 3.0};
  EXPECT_TRUE(withinTolerances(error, {}));
  EXPECT_TRUE(withinTolerances(error, {0.05, 0, 0}));  // on the bound is within
  EXPECT_FALSE(withinTolerances(error, {0.049, 0, 0}));
  EXPECT_FALSE(withinTolerances(error, {0, 0.1, 0}));
  EXPECT_TRUE(withinTolerances(error, {0, 0.2, 0}));
  EXPECT_FALSE(withinTolerances(error, {1, 1, 2.9}));
  EXPECT_FALSE(withinTolerances({NAN, 0, 0}, {0.1, 0, 0}));  // an error that is not a number is out
}

TEST(Tolerances, ConstraintsAreReadAsRosControllersReadsThem) {
  const ParameterTree constraints = ParameterTree::fromYaml(
      "goal_time: 0.6\nshoulder: {trajectory: 0.1, goal: 0.02}\nwrist: {goal: 0.03}\nwirst: {goal: 1}\n",
      "yaml");
  std::vector<std::string> warnings;
  const auto tolerances = readConstraints(constraints, {"shoulder", "wrist"}, "arm_controller", &warnings);
  ASSERT_THAT(tolerances, SizeIs(2));
  EXPECT_DOUBLE_EQ(tolerances[0].path.position, 0.1);
  EXPECT_DOUBLE_EQ(tolerances[0].goal.position, 0.02);
  EXPECT_DOUBLE_EQ(tolerances[0].goal.velocity, 0.01);  // stopped_velocity_tolerance's default
  EXPECT_DOUBLE_EQ(tolerances[1].path.position, 0);
  EXPECT_DOUBLE_EQ(tolerances[1].goal.position, 0.03);
  EXPECT_DOUBLE_EQ(tolerances[1].goal_time, 0.6);
  ASSERT_THAT(warnings, SizeIs(1));
  EXPECT_THAT(warnings[0], HasSubstr("constraints/wirst"));
  EXPECT_THAT(warnings[0], HasSubstr("did you mean [wrist]?"));
  EXPECT_THROW(readConstraints(ParameterTree::fromYaml("goal_time: -1", "yaml"), {"a"}, "c", nullptr),
               std::invalid_argument);
}

TEST(Tolerances, AGoalReplacesLiftsOrKeepsEachDefault) {
  std::vector<JointTolerances> defaults(2);
  defaults[0].path = {0.1, 0.2, 0};
  defaults[0].goal = {0.02, 0.01, 0};
  defaults[1].path = {0.1, 0, 0};
  for (auto& tolerances : defaults) tolerances.goal_time = 0.5;
  FollowJointTrajectoryAction::Goal goal;
  goal.path_tolerance = {{"shoulder", 0.3, -1, 0}, {"elbow", 9, 9, 9}};
  goal.goal_tolerance = {{"wrist", 0, 0, 0.4}};
  goal.goal_time_tolerance = -1;
  const auto changed = goalTolerances(goal, {"shoulder", "wrist"}, defaults);
  EXPECT_DOUBLE_EQ(changed[0].path.position, 0.3);   // > 0 replaces
  EXPECT_DOUBLE_EQ(changed[0].path.velocity, 0);     // < 0 lifts
  EXPECT_DOUBLE_EQ(changed[0].goal.position, 0.02);  // 0 keeps
  EXPECT_DOUBLE_EQ(changed[1].goal.acceleration, 0.4);
  EXPECT_DOUBLE_EQ(changed[1].path.position, 0.1);
  EXPECT_DOUBLE_EQ(changed[0].goal_time, 0);
  goal.goal_time_tolerance = 2;
  EXPECT_DOUBLE_EQ(goalTolerances(goal, {"shoulder", "wrist"}, defaults)[1].goal_time, 2);
}

/// A message for the joints `names` with one waypoint per entry of `positions` (one row per waypoint) at
/// `times`.
JointTrajectory message(const std::vector<std::string>& names,
                        const std::vector<std::vector<double>>& positions, const std::vector<double>& times,
                        double stamp = 0) {
  JointTrajectory trajectory;
  trajectory.stamp = stamp;
  trajectory.joint_names = names;
  for (size_t k = 0; k < positions.size(); ++k)
    trajectory.points.push_back({positions[k], {}, {}, {}, times[k]});
  return trajectory;
}

class Merge : public ::testing::Test {
 protected:
  std::vector<JointSegments> merged(const JointTrajectory& trajectory, double time, GoalId goal = 7,
                                    bool allow_partial = false) {
    return mergeTrajectory(trajectory, time, {joints, continuous, current, goal, {}, allow_partial});
  }
  std::string refusal(const JointTrajectory& trajectory, double time, bool allow_partial = false) {
    try {
      merged(trajectory, time, 7, allow_partial);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  }

  std::vector<std::string> joints = {"shoulder", "wrist"};
  std::vector<bool> continuous = {false, true};
  std::vector<JointSegments> current = holdTrajectory({0.2, 0.0}, 0, 0);
};

TEST_F(Merge, ATrajectoryStartsFromWhereTheJointsAreAtItsStart) {
  // From rest at 0.2 at t = 1: a line to 1.2 at t = 3, then to 0.2 at t = 4. The waypoint at 0 s is dropped.
  const auto trajectory =
      merged(message({"shoulder", "wrist"}, {{9, 9}, {1.2, 0.5}, {0.2, -0.5}}, {0, 2, 3}), 1.0);
  ASSERT_THAT(trajectory[0], SizeIs(3));  // the hold, the segment from it, the message's segment
  EXPECT_NEAR(sample(trajectory[0], 0.5).position, 0.2, kTight);
  EXPECT_NEAR(sample(trajectory[0], 2.0).position, 0.7, kTight);
  EXPECT_NEAR(sample(trajectory[0], 3.0).position, 1.2, kTight);
  EXPECT_NEAR(sample(trajectory[0], 3.5).position, 0.7, kTight);
  EXPECT_NEAR(sample(trajectory[0], 9.0).position, 0.2, kTight);
  EXPECT_EQ(trajectory[0][0].goal, 0u);  // the hold serves no goal; the new segments serve the new one
  EXPECT_EQ(trajectory[0][1].goal, 7u);
  EXPECT_EQ(trajectory[1].back().goal, 7u);
}

TEST_F(Merge, ANewTrajectoryReplacesTheOldOneMidWayFromItsFirstWaypoint) {
  current = merged(message({"shoulder", "wrist"}, {{1.2, 0}, {2.2, 0}}, {2, 4}), 0.0, 1);
  // At t = 3, half way to 2.2: a new one to -1 at t = 4 (1 s from now). The old runs until t = 3, a segment
  // leads from where it is then (1.7) to -1.
  const auto trajectory = merged(message({"wrist", "shoulder"}, {{0, -1.0}}, {1}), 3.0, 2);
  EXPECT_NEAR(sample(trajectory[0], 2.5).position, 1.45, kTight);  // the old one, still
  EXPECT_NEAR(sample(trajectory[0], 3.0).position, 1.7, kTight);   // joined without a jump
  EXPECT_NEAR(sample(trajectory[0], 3.5).position, 0.35, kTight);
  EXPECT_NEAR(sample(trajectory[0], 4.0).position, -1.0, kTight);
  EXPECT_EQ(findSegment(trajectory[0], 2.5)->goal, 1u);  // old segments keep their goal
  EXPECT_EQ(findSegment(trajectory[0], 3.5)->goal, 2u);
}

TEST_F(Merge, AStampInTheFutureLetsTheOldOneRunUntilThenAndOneInThePastDropsWhatIsOver) {
  current = merged(message({"shoulder", "wrist"}, {{1.2, 0}}, {1}), 0.0, 1);
  const auto later = merged(message({"shoulder", "wrist"}, {{0.0, 0}}, {1}, /*stamp=*/5.0), 0.5);
  EXPECT_NEAR(sample(later[0], 4.0).position, 1.2, kTight);  // the old one holds its end until t = 5
  EXPECT_NEAR(sample(later[0], 5.5).position, 0.6, kTight);
  EXPECT_NEAR(sample(later[0], 6.0).position, 0.0, kTight);
  // Stamped at t = 1 and taken at t = 2: its first waypoint (t = 1.5) is over, the second (t = 3) is next.
  const auto past = merged(message({"shoulder", "wrist"}, {{5, 0}, {0.2, 0}}, {0.5, 2}, /*stamp=*/1.0), 2.0);
  EXPECT_NEAR(sample(past[0], 2.0).position, sample(current[0], 2.0).position, kTight);
  EXPECT_NEAR(sample(past[0], 3.0).position, 0.2, kTight);
  EXPECT_THAT(refusal(message({"shoulder", "wrist"}, {{5, 0}}, {0.5}, 1.0), 2.0),
              HasSubstr("all 1 waypoints are in the past"));
}

TEST_F(Merge, AContinuousJointTakesTheShortWayRound) {
  current = holdTrajectory({0.0, 3.0}, 0, 0);
  const auto trajectory = merged(message({"shoulder", "wrist"}, {{0, -3.0}, {0, -2.9}}, {1, 2}), 0.0);
  // -3.0 is 2 pi - 6.0 = 0.283 rad beyond 3.0 counter-clockwise: it goes there, and on by 0.1.
  EXPECT_NEAR(sample(trajectory[1], 1.0).position, 2 * M_PI - 3.0, kTight);
  EXPECT_NEAR(sample(trajectory[1], 2.0).position, 2 * M_PI - 2.9, kTight);
  EXPECT_DOUBLE_EQ(wraparoundOffset(3.0, -3.0, false), 0);
}

TEST_F(Merge, JointsNotNamedKeepTheirTrajectoryWhenPartialGoalsAreAllowed) {
  current = merged(message({"shoulder", "wrist"}, {{1.0, 1.0}}, {2}), 0.0, 1);
  EXPECT_THAT(refusal(message({"wrist"}, {{0.0}}, {1}), 1.0),
              HasSubstr("allow_partial_joints_goal is false"));
  const auto trajectory = merged(message({"wrist"}, {{0.0}}, {1}), 1.0, 3, /*allow_partial=*/true);
  EXPECT_NEAR(sample(trajectory[0], 2.0).position, 1.0, kTight);
  EXPECT_EQ(findSegment(trajectory[0], 1.5)->goal, 3u);  // now serving the new goal
  EXPECT_NEAR(sample(trajectory[1], 2.0).position, 0.0, kTight);
}

TEST_F(Merge, WhatCannotBeFollowedIsRefusedWithTheReason) {
  EXPECT_THAT(refusal(message({"shoulder", "elbow"}, {{0, 0}}, {1}), 0), HasSubstr("[elbow] is not one"));
  EXPECT_THAT(refusal(message({"shoulder", "shoulder"}, {{0, 0}}, {1}), 0), HasSubstr("named twice"));
  EXPECT_THAT(refusal(message({"shoulder", "wrist"}, {{0, 0}, {1, 1}}, {1, 1}), 0),
              HasSubstr("increase strictly"));
  EXPECT_THAT(refusal(message({"shoulder", "wrist"}, {{0}}, {1}), 0), HasSubstr("1 positions for 2 joints"));
  EXPECT_THAT(refusal(message({"shoulder", "wrist"}, {{0, NAN}}, {1}), 0), HasSubstr("not numbers"));
  auto velocities = message({"shoulder", "wrist"}, {{0, 0}}, {1});
  velocities.points[0].velocities = {1};
  EXPECT_THAT(refusal(velocities, 0), HasSubstr("1 velocities for 2 joints"));
  EXPECT_THAT(refusal(JointTrajectory{0, joints, {}}, 0), HasSubstr("no waypoints"));
}

TEST(StopTrajectory, ComesToRestWithinItsDurationWhereTheQuinticTurnsBack) {
  const auto stop = stopTrajectory({{1.0, 2.0, 0.0}}, 10.0, 0.5, 0);
  ASSERT_THAT(stop, SizeIs(1));
  expectMotion(sample(stop[0], 10.0), 1.0, 2.0, 0.0, "start");
  // The quintic from (1, 2, 0) to (1, -2, 0) over 1 s: symmetric about its middle, at rest there, 1 + 5/16
  // on.
  const JointMotion end = sample(stop[0], 10.5);
  EXPECT_NEAR(end.position, 1.0 + 2.0 * 0.5 * 5 / 8, 1e-9);
  EXPECT_NEAR(end.velocity, 0, 1e-9);
  EXPECT_NEAR(sample(stop[0], 11.0).position, end.position, kTight);
  const auto hold = holdTrajectory({0.4}, 1.0, 5);
  expectMotion(sample(hold[0], 3.0), 0.4, 0, 0, "hold");
  EXPECT_EQ(hold[0][0].goal, 5u);
}

}  // namespace
}  // namespace bullet_sim
