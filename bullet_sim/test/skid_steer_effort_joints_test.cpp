// A skid-steer drive on wheels that also have effort transmissions under gazebo_ros_control, with no
// controller claiming them (issue 30, B6: ROSbot 2 crept unbidden and ignored cmd_vel). In Gazebo,
// DefaultRobotHWSim writes effort 0 to an unclaimed effort joint, SetForce(0), which adds nothing to the
// skid-steer plugin's velocity motor on the same joint: the robot stands still with no command and drives at
// the commanded speed.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_support.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {
namespace {

const char* const kWheels[] = {"front_left_wheel_joint", "front_right_wheel_joint", "rear_left_wheel_joint",
                               "rear_right_wheel_joint"};

/// The light skid-steer look-alike with its body's mass 3 cm forward (ROSbot's is too), its drive updating at
/// 10 Hz, and after it gazebo_ros_control with an effort transmission on each wheel.
std::string skidSteerWithEffortJoints() {
  std::string urdf = test::readFile(test::fixture("contact/light_skid_steer.urdf"));
  urdf = test::replaceAfter(urdf, "<link name=\"base_link\">", "<origin xyz=\"0 0 0.03\"/>",
                            "<origin xyz=\"0.03 0 0.03\"/>");
  urdf = test::replaceAfter(urdf, "libgazebo_ros_skid_steer_drive.so", "<torque>1</torque>",
                            "<torque>1</torque><updateRate>10</updateRate>");
  std::string more = "<gazebo><plugin name=\"gazebo_ros_control\" filename=\"libgazebo_ros_control.so\">"
                     "<robotNamespace>/</robotNamespace></plugin></gazebo>";
  for (const char* joint : kWheels) {
    const std::string name = joint;
    more += "<transmission name=\"" + name + "_trans\">"
            "<type>transmission_interface/SimpleTransmission</type>"
            "<joint name=\"" + name + "\"><hardwareInterface>hardware_interface/EffortJointInterface"
            "</hardwareInterface></joint>"
            "<actuator name=\"" + name + "_motor\"><mechanicalReduction>1</mechanicalReduction></actuator>"
            "</transmission>";
  }
  return test::replaceAfter(urdf, "</gazebo>", "</robot>", more + "</robot>");
}

class SkidSteerEffortJoints : public ::testing::TestWithParam<std::string> {};

TEST_P(SkidSteerEffortJoints, StandStillUnbiddenAndDriveAtTheCommandedSpeed) {
  TreeParameters parameters(ParameterTree::fromYaml(
      "joint_state_controller: {type: joint_state_controller/JointStateController, publish_rate: 50}",
      "yaml"));
  SimulationOptions options;
  options.parameters = &parameters;
  Simulation simulation(test::emptyWorld(), options);
  const ModelSpec model =
      test::parseQuietly(test::withWheelModel(skidSteerWithEffortJoints(), GetParam()), "skid steer");
  Robot& robot = simulation.spawn("robot", model, {});
  ASSERT_EQ(robot.wheelModel(), GetParam());
  test::startControllers(test::pluginsOf<RosControl>(robot).at(0)->controllerManager(),
                         {"joint_state_controller"}, simulation.time());
  const auto x = [&] { return robot.body().linkPose("base_footprint").translation().x(); };
  const long second = std::lround(1.0 / simulation.stepSize());

  for (long k = 0; k < 5 * second; ++k) simulation.step();  // no command: the drive holds its wheels
  EXPECT_NEAR(x(), 0.0, 0.005) << "crept with no command";

  // 0.3 m/s: after 1 s of spin-up, 2 s at v cover v * 2 s.
  WheeledDrive& drive = *test::pluginsOf<WheeledDrive>(robot).at(0);
  const double v = 0.3;
  double x0 = 0;
  for (long k = 0; k < 3 * second; ++k) {
    if (k % 100 == 0) {
      ASSERT_TRUE(drive.setCommand(v, 0, simulation.time()));
    }
    if (k == second) x0 = x();
    simulation.step();
  }
  EXPECT_NEAR(x() - x0, v * 2.0, 0.05 * v * 2.0);
}

INSTANTIATE_TEST_SUITE_P(WheelModels, SkidSteerEffortJoints, ::testing::ValuesIn(test::kWheelModels),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace bullet_sim
