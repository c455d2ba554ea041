// Planar move against closed forms, on the multi-sensor test robot (whose frictionless casters let nothing
// but the plugin move it). Stepped in-process, no roscore.
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/simulation/simulation.h"
#include "plugins/planar_move/planar_move.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using test::angleDifference;
using test::multiSensorRobot;
using test::multiSensorUrdf;
using test::parseExpecting;
using test::Planar;
using test::planar;
using test::drivePlanar;
using test::twist;

/// Where a body starting at `start` ends after `seconds` at the body-frame velocity (vx, vy) [m/s] turning
/// at w [rad/s] (w != 0).
Planar holonomicArc(const Planar& start, double vx, double vy, double w, double seconds) {
  const double yaw = start.yaw + w * seconds;
  const double s0 = std::sin(start.yaw), c0 = std::cos(start.yaw), s = std::sin(yaw), c = std::cos(yaw);
  return {start.x + (vx * (s - s0) + vy * (c - c0)) / w, start.y + (-vx * (c - c0) + vy * (s - s0)) / w, yaw};
}

const SpawnPose kStart{.x = 0.5, .y = -0.3, .yaw = 0.4};

TEST(PlanarMove, FollowsTheClosedFormOfAHolonomicArc) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", multiSensorRobot(), kStart);
  PlanarMove& planar_move = *test::pluginsOf<PlanarMove>(robot).at(0);
  drivePlanar(simulation, planar_move, twist(0.3, 0.2, 0.5), 4.0);
  const Planar truth = holonomicArc({kStart.x, kStart.y, kStart.yaw}, 0.3, 0.2, 0.5, 4.0);
  const Planar base = planar(robot.body().linkPose("base_footprint"));
  EXPECT_NEAR(base.x, truth.x, 2e-3);
  EXPECT_NEAR(base.y, truth.y, 2e-3);
  EXPECT_NEAR(angleDifference(base.yaw, truth.yaw), 0, 1e-3);
  EXPECT_NEAR(robot.body().linkPose("base_footprint").translation().z(), 0, 2e-3) << "it stays on the ground";
}

TEST(PlanarMove, OdometryIsTheBasePoseAndAgreesWithItsTf) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", multiSensorRobot(), kStart);
  PlanarMove& planar_move = *test::pluginsOf<PlanarMove>(robot).at(0);
  const auto& outputs = planar_move.ports().outputs;
  ASSERT_EQ(outputs.size(), 2u);
  EXPECT_EQ(outputs[0].topic, "odom");
  const auto* tf = std::get<const Stream<TransformSample>*>(outputs[1].stream);
  drivePlanar(simulation, planar_move, twist(0.3, 0.2, 0.5), 2.0);
  const Odometry& odometry = test::latestOf<Odometry>(planar_move);
  EXPECT_NEAR(odometry.stamp, 2.0, 1e-9) << "50 Hz";
  EXPECT_EQ(odometry.frame_id, "odom");
  EXPECT_EQ(odometry.child_frame_id, "base_footprint");
  EXPECT_TRUE(odometry.pose.isApprox(robot.body().linkPose("base_footprint"), 1e-12));
  ASSERT_EQ(tf->latest().frames.size(), 1u);
  EXPECT_EQ(tf->latest().frames[0].parent, "odom");
  EXPECT_EQ(tf->latest().frames[0].child, "base_footprint");
  EXPECT_TRUE(tf->latest().frames[0].pose.isApprox(odometry.pose, 1e-12));
  EXPECT_DOUBLE_EQ(tf->latest().stamp, odometry.stamp);
  // The velocity over the last 20 ms, in the base frame.
  EXPECT_NEAR(odometry.linear_velocity.x(), 0.3, 5e-3);
  EXPECT_NEAR(odometry.linear_velocity.y(), 0.2, 5e-3);
  EXPECT_NEAR(odometry.angular_velocity.z(), 0.5, 1e-3);
  EXPECT_DOUBLE_EQ(odometry.pose_covariance[0], 1e-5);
  EXPECT_DOUBLE_EQ(odometry.pose_covariance[35], 1e-3);
}

TEST(PlanarMove, StopsAfterCmdTimeoutAndIgnoresNonFiniteCommands) {
  const std::string urdf =
      test::withPluginTags(multiSensorUrdf(), "libgazebo_ros_planar_move.so", {{"cmdTimeout", "0.5"}});
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "timeout"), {});
  PlanarMove& planar_move = *test::pluginsOf<PlanarMove>(robot).at(0);
  ASSERT_TRUE(planar_move.setCommand(twist(0.4, 0, 0), simulation.time()));
  EXPECT_FALSE(planar_move.setCommand(twist(NAN, 0, 0), simulation.time()));
  for (int i = 0; i < 2000; ++i) simulation.step();
  // 0.5 s at 0.4 m/s, then nothing.
  EXPECT_NEAR(robot.body().linkPose("base_footprint").translation().x(), 0.2, 2e-3);
}

}  // namespace
}  // namespace bullet_sim
