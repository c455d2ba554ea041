// Ridgeback's and Nexus' copies of the force-based move on the multi-sensor test robot (frictionless casters:
// nothing but the plugin moves it), against closed forms. Stepped in-process, no roscore.
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/simulation/simulation.h"
#include "plugins/force_based_move_copies/force_based_move_copies.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using test::drivePlanar;
using test::twist;

/// The multi-sensor robot without its drive, driven by the copy `filename` with `tags`.
ModelSpec robotWith(const std::string& filename, const test::Tags& tags) {
  const std::string urdf = test::withPlugin(test::multiSensorUrdf("none"), "base_controller", filename, tags);
  return test::parseExpecting(urdf, filename);
}

/// The base's velocity in its own frame: x, y [m/s] and yaw rate [rad/s].
Eigen::Vector3d baseVelocity(const Robot& robot) {
  const Eigen::Isometry3d base = robot.body().linkPose("base_footprint");
  const Eigen::Vector3d linear =
      base.linear().transpose() * robot.body().linkLinearVelocity("base_footprint");
  return {linear.x(), linear.y(), robot.body().linkAngularVelocity("base_footprint").z()};
}

double totalMass(const ModelSpec& model) {
  double mass = 0;
  for (const auto& link : model.links) mass += link.inertial ? link.inertial->mass : 0;
  return mass;
}

TEST(RidgebackForceBasedMove, DrivenSidewaysAndTurningReachesTheCommandAndStopsWhenCmdVelFallsSilent) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn(
      "ridgeback", robotWith("libridgeback_ros_force_based_move.so",
                             {{"robotBaseFrame", "base_footprint"}, {"yaw_velocity_p_gain", "500"}}), {});
  ASSERT_EQ(test::pluginsOf<ForceBasedMove>(robot).size(), 1u);
  ForceBasedMove& drive = *test::pluginsOf<ForceBasedMove>(robot).at(0);
  drivePlanar(simulation, drive, twist(0, 0.3, 0.4), 3.0);  // cmd_vel at 10 Hz, within the 0.25 s timeout
  const Eigen::Vector3d driven = baseVelocity(robot);
  EXPECT_NEAR(driven.x(), 0, 2e-3);
  EXPECT_NEAR(driven.y(), 0.3, 2e-3);
  EXPECT_NEAR(driven.z(), 0.4, 2e-3);
  EXPECT_NEAR(robot.body().linkPose("base_footprint").translation().z(), 0, 2e-3) << "it does not tip";

  // cmd_vel silent: after cmdVelTimeOut (0.25 s) the forces brake the base to rest.
  test::stepSending(simulation, 0.5, [] { return true; });
  EXPECT_LT(baseVelocity(robot).norm(), 2e-3) << baseVelocity(robot).transpose();
}

TEST(NexusForceBasedMove, DefaultGainsFollowTheFirstOrderLawUpToThePositiveCap) {
  // Nexus' defaults: 15 N s/m, so v(t) = v_cmd (1 - exp(-15 t / m)); linear.x is capped at 0.6 m/s, a
  // negative linear.y is not capped.
  const ModelSpec model = robotWith("libnexus_ros_force_based_move.so", {});
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("nexus", model, {});
  ForceBasedMove& drive = *test::pluginsOf<ForceBasedMove>(robot).at(0);
  const double seconds = 2.0;
  drivePlanar(simulation, drive, twist(1.0, -0.7, 0), seconds);
  const double reached = 1 - std::exp(-15 * seconds / totalMass(model));
  const Eigen::Vector3d velocity = baseVelocity(robot);
  EXPECT_NEAR(velocity.x(), 0.6 * reached, 0.02 * 0.6 * reached);
  EXPECT_NEAR(velocity.y(), -0.7 * reached, 0.02 * 0.7 * reached);
}

TEST(NexusForceBasedMove, CapsEachAxisAtItsOwnMaximum) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("nexus",
                                  robotWith("libnexus_ros_force_based_move.so",
                                            {{"x_velocity_p_gain", "10000"},
                                             {"y_velocity_p_gain", "10000"},
                                             {"yaw_velocity_p_gain", "100"},
                                             {"max_y_velocity", "0.2"},
                                             {"max_yaw_velocity", "0.3"}}),
                                  {});
  ForceBasedMove& drive = *test::pluginsOf<ForceBasedMove>(robot).at(0);
  drivePlanar(simulation, drive, twist(0.1, 0.5, 0.8), 3.0);
  const Eigen::Vector3d velocity = baseVelocity(robot);
  EXPECT_NEAR(velocity.x(), 0.1, 2e-3);
  EXPECT_NEAR(velocity.y(), 0.2, 2e-3);
  EXPECT_NEAR(velocity.z(), 0.3, 2e-3);
}

}  // namespace
}  // namespace bullet_sim
