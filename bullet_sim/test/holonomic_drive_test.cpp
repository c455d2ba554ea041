// hector's IMU and GPS on the multi-sensor test robot while planar move drives it (its frictionless casters let
// nothing but the plugin move it). Stepped in-process, no roscore. Planar move's and force-based move's own
// tests are in their folders.
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/hector_gps/hector_gps.h"
#include "plugins/hector_imu/hector_imu.h"
#include "plugins/planar_move/planar_move.h"
#include "bullet_sim/simulation/simulation.h"
#include "multi_sensor_robot.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using test::multiSensorUrdf;
using test::parseExpecting;
using test::twist;

/// Steps `seconds`, sending `command` to `drive` every 0.1 s as `rostopic pub -r 10` does.
void drive(Simulation& simulation, PlanarMove& drive, const Twist& command, double seconds) {
  test::stepSending(simulation, seconds, [&] { return drive.setCommand(command, simulation.time()); });
}

const SpawnPose kStart{.x = 0.5, .y = -0.3, .yaw = 0.4};

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
