// The Yahboom car's pan/tilt held by the joint position plugin, on each wheel model. Stepped in-process, no
// roscore.
#include <gtest/gtest.h>

#include "bullet_sim/simulation/simulation.h"
#include "plugins/joint_position/joint_position.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

TEST(JointPosition, PanTiltHoldsItsPositionAgainstGravity) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("car", test::yahboomcar(wheel_model), {});
    auto* pan_tilt = test::pluginsOf<JointPosition>(robot).at(0);
    for (int i = 0; i < 1000; ++i) simulation.step();
    EXPECT_NEAR(robot.body().jointPosition(robot.body().jointIndex("jq2_Joint")), 0, 0.01);
    ASSERT_TRUE(pan_tilt->setTarget("jq1_Joint", 0.5));
    for (int i = 0; i < 2000; ++i) simulation.step();
    EXPECT_NEAR(robot.body().jointPosition(robot.body().jointIndex("jq1_Joint")), 0.5, 0.01);
  }
}

TEST(JointPosition, PanTiltHoldsWhereItSpawns) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    SpawnPose pose;
    pose.joints = {{"jq1_Joint", 0.3}};
    Robot& robot = simulation.spawn("car", test::yahboomcar(wheel_model), pose);
    for (int i = 0; i < 1000; ++i) simulation.step();
    EXPECT_NEAR(robot.body().jointPosition(robot.body().jointIndex("jq1_Joint")), 0.3, 0.01);
  }
}

}  // namespace
}  // namespace bullet_sim
