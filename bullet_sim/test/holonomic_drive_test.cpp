// Planar move and hector's force-based move against closed forms, on the multi-sensor test robot (whose
// frictionless casters let nothing but the plugins move it); hector's IMU and GPS on the moving robot.
// Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/force_based_move/force_based_move.h"
#include "plugins/hector_gps/hector_gps.h"
#include "plugins/hector_imu/hector_imu.h"
#include "plugins/planar_move/planar_move.h"
#include "bullet_sim/simulation/simulation.h"
#include "multi_sensor_robot.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::Contains;
using ::testing::HasSubstr;
using test::angleDifference;
using test::multiSensorRobot;
using test::multiSensorUrdf;
using test::parseExpecting;
using test::Planar;
using test::planar;


/// Where a body starting at `start` ends after `seconds` at the body-frame velocity (vx, vy) [m/s] turning
/// at w [rad/s] (w != 0).
Planar holonomicArc(const Planar& start, double vx, double vy, double w, double seconds) {
  const double yaw = start.yaw + w * seconds;
  const double s0 = std::sin(start.yaw), c0 = std::cos(start.yaw), s = std::sin(yaw), c = std::cos(yaw);
  return {start.x + (vx * (s - s0) + vy * (c - c0)) / w, start.y + (-vx * (c - c0) + vy * (s - s0)) / w, yaw};
}

/// Steps `seconds`, sending `command` to `drive` every 0.1 s as `rostopic pub -r 10` does.
void drive(Simulation& simulation, PlanarMove& drive, const Twist& command, double seconds) {
  const auto steps = std::lround(seconds / simulation.stepSize());
  for (long i = 0; i < steps; ++i) {
    if (i % 100 == 0) ASSERT_TRUE(drive.setCommand(command, simulation.time()));
    simulation.step();
  }
}

Twist twist(double x, double y, double yaw_rate) {
  Twist command;
  command.linear = {x, y, 0};
  command.angular = {0, 0, yaw_rate};
  return command;
}

const SpawnPose kStart{.x = 0.5, .y = -0.3, .yaw = 0.4};

TEST(PlanarMove, FollowsTheClosedFormOfAHolonomicArc) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", multiSensorRobot(), kStart);
  PlanarMove& planar_move = *test::pluginsOf<PlanarMove>(robot).at(0);
  drive(simulation, planar_move, twist(0.3, 0.2, 0.5), 4.0);
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
  drive(simulation, planar_move, twist(0.3, 0.2, 0.5), 2.0);
  const Odometry& odometry = planar_move.odometry();
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

TEST(ForceBasedMove, ReachesTheCommandedVelocitiesAndDeadReckonsItsOdometry) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", multiSensorRobot("force_based"), kStart);
  ASSERT_TRUE(test::pluginsOf<PlanarMove>(robot).size() == 1 && test::pluginsOf<ForceBasedMove>(robot).size() == 1);
  ForceBasedMove& force_based = *test::pluginsOf<ForceBasedMove>(robot).at(0);
  const Eigen::Isometry3d start = robot.body().linkPose("base_footprint");
  drive(simulation, force_based, twist(0.3, 0.2, 0.5), 3.0);
  const Eigen::Isometry3d base = robot.body().linkPose("base_footprint");
  const Eigen::Vector3d velocity =
      base.linear().transpose() * robot.body().linkLinearVelocity("base_footprint");
  // P control on a frictionless base: the steady error is the turning frame's, m w v / k = 0.4 mm/s.
  EXPECT_NEAR(velocity.x(), 0.3, 2e-3);
  EXPECT_NEAR(velocity.y(), 0.2, 2e-3);
  EXPECT_NEAR(robot.body().linkAngularVelocity("base_footprint").z(), 0.5, 2e-3);
  EXPECT_NEAR(base.translation().z(), 0, 2e-3) << "pushed at its centre of mass, it does not tip";
  // Odometry: dead reckoning from the start pose.
  const Odometry& odometry = force_based.odometry();
  const Planar travelled = planar(start.inverse() * base);
  const Planar reckoned = planar(odometry.pose);
  EXPECT_NEAR(reckoned.x, travelled.x, 0.01);
  EXPECT_NEAR(reckoned.y, travelled.y, 0.01);
  EXPECT_NEAR(angleDifference(reckoned.yaw, travelled.yaw), 0, 0.01);
  EXPECT_NEAR(odometry.linear_velocity.x(), 0.3, 2e-3);
  EXPECT_NEAR(odometry.angular_velocity.z(), 0.5, 2e-3);
  EXPECT_DOUBLE_EQ(odometry.pose_covariance[35], 100) << "hector's: turning";
}

TEST(ForceBasedMove, HectorsArcIsExactForAConstantTwist) {
  // Half a turn at 0.5 rad/s with 0.3 m/s forward: a semicircle of radius 0.6 m.
  const Eigen::Isometry3d motion = motionOver(0.3, 0, 0.5, M_PI / 0.5);
  EXPECT_TRUE(motion.translation().isApprox(Eigen::Vector3d(0, 1.2, 0), 1e-12));
  EXPECT_NEAR(planar(motion).yaw, M_PI, 1e-12);
  EXPECT_TRUE(motionOver(0.3, 0.2, 0, 2).translation().isApprox(Eigen::Vector3d(0.6, 0.4, 0)));
}

TEST(ForceBasedMove, LoadMessages) {
  const std::string urdf =
      test::withPluginTags(multiSensorUrdf("force_based"), "libgazebo_ros_force_based_move.so",
                           {{"robotBaseFrame", "base_footprnt"}, {"x_velocity_p_gain", "-1"}});
  EXPECT_THAT(test::loadErrors(urdf),
              testing::IsSupersetOf({HasSubstr("<robotBaseFrame> [base_footprnt] is not a link (did you mean "
                                               "[base_footprint]?); the forces act on that link"),
                                     HasSubstr("<x_velocity_p_gain> must be >= 0, not -1")}));
}

// hector's IMU and GPS on the moving robot.

TEST(HectorImu, WithoutErrorsMatchesTheGroundTruthWhileTurning) {
  const std::string urdf = test::withPluginTags(
      multiSensorUrdf(), "libhector_gazebo_ros_imu.so",
      {{"accelDrift", "0 0 0"}, {"accelGaussianNoise", "0 0 0"}, {"rateDrift", "0 0 0"},
       {"rateGaussianNoise", "0 0 0"}, {"yawDrift", "0"}, {"yawGaussianNoise", "0"}});
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "ideal imu"), kStart);
  drive(simulation, *test::pluginsOf<PlanarMove>(robot).at(0), twist(0.3, 0.2, 0.5), 2.0);
  const ImuSample& sample = test::pluginsOf<HectorImu>(robot).at(0)->sample();
  // On the turning axis, moving at v in its frame and turning at w: it feels w x v and gravity.
  EXPECT_LT((sample.angular_velocity - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-3);
  EXPECT_LT((sample.linear_acceleration - Eigen::Vector3d(-0.5 * 0.2, 0.5 * 0.3, 9.81)).norm(), 0.01);
  const Eigen::Quaterniond truth(robot.body().linkPose("imu_link").linear());
  EXPECT_LT(sample.orientation.angularDistance(truth), 1e-9);
}

TEST(HectorGps, TheVelocityReadsNorthAndWest) {
  const std::string urdf =
      test::withPluginTags(multiSensorUrdf(), "libhector_gazebo_ros_gps.so", {{"drift", "0 0 0"}});
  for (const auto& [command, north_west] : {std::make_pair(twist(0.3, 0, 0), Eigen::Vector3d(0.3, 0, 0)),
                                            std::make_pair(twist(0, 0.3, 0), Eigen::Vector3d(0, 0.3, 0))}) {
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "gps"), {});
    drive(simulation, *test::pluginsOf<PlanarMove>(robot).at(0), command, 1.0);
    const Vector3Sample& velocity = test::pluginsOf<HectorGps>(robot).at(0)->velocity();
    EXPECT_LT((velocity.vector - north_west).norm(), 1e-3) << velocity.vector.transpose();
    EXPECT_EQ(velocity.frame_id, "gps_link");
  }
}

}  // namespace
}  // namespace bullet_sim
