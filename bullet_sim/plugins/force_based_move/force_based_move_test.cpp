// hector's force-based move against closed forms, on the multi-sensor test robot (whose frictionless casters
// let nothing but the plugin move it). Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/simulation/simulation.h"
#include "plugins/force_based_move/force_based_move.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
using test::angleDifference;
using test::multiSensorRobot;
using test::multiSensorUrdf;
using test::Planar;
using test::planar;
using test::drivePlanar;
using test::twist;

const SpawnPose kStart{.x = 0.5, .y = -0.3, .yaw = 0.4};

TEST(ForceBasedMove, ReachesTheCommandedVelocitiesAndDeadReckonsItsOdometry) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", multiSensorRobot("force_based"), kStart);
  ASSERT_TRUE(test::pluginsOf<PlanarMove>(robot).size() == 1 &&
              test::pluginsOf<ForceBasedMove>(robot).size() == 1);
  ForceBasedMove& force_based = *test::pluginsOf<ForceBasedMove>(robot).at(0);
  const Eigen::Isometry3d start = robot.body().linkPose("base_footprint");
  drivePlanar(simulation, force_based, twist(0.3, 0.2, 0.5), 3.0);
  const Eigen::Isometry3d base = robot.body().linkPose("base_footprint");
  const Eigen::Vector3d velocity =
      base.linear().transpose() * robot.body().linkLinearVelocity("base_footprint");
  // P control on a frictionless base: the steady error is the turning frame's, m w v / k = 0.4 mm/s.
  EXPECT_NEAR(velocity.x(), 0.3, 2e-3);
  EXPECT_NEAR(velocity.y(), 0.2, 2e-3);
  EXPECT_NEAR(robot.body().linkAngularVelocity("base_footprint").z(), 0.5, 2e-3);
  EXPECT_NEAR(base.translation().z(), 0, 2e-3) << "pushed at its centre of mass, it does not tip";
  // Odometry: dead reckoning from the start pose.
  const Odometry& odometry = test::latestOf<Odometry>(force_based);
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

}  // namespace
}  // namespace bullet_sim
