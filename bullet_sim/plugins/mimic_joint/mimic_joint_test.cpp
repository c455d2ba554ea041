// Mimic joints: a look-alike two-finger gripper (test/fixtures/robots/two_finger_gripper.urdf) whose right
// finger follows the left by URDF's <mimic> or by a mimic joint plugin, on each wheel model. Stepped
// in-process.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bullet_sim/simulation/simulation.h"
#include "plugins/joint_position/joint_position.h"
#include "plugins/joint_states/joint_states.h"
#include "plugins/mimic_joint/mimic_joint.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

constexpr char kPlugin[] = "libroboticsgroup_upatras_gazebo_mimic_joint_plugin.so";

std::string gripper(const std::string& wheel_model) {
  return test::withWheelModel(test::readFile(test::fixture("robots/two_finger_gripper.urdf")), wheel_model);
}

/// The gripper without its <mimic>: only a plugin couples the fingers then.
std::string gripperWithoutMimic(const std::string& wheel_model) {
  return test::editUrdf(gripper(wheel_model), [](tinyxml2::XMLElement& robot) {
    for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
      if (auto* mimic = joint->FirstChildElement("mimic")) joint->DeleteChild(mimic);
    }
  });
}

std::string withMimicPlugin(const std::string& urdf, const test::Tags& more = {}) {
  test::Tags tags = {{"joint", "left_finger_joint"}, {"mimicJoint", "right_finger_joint"}};
  tags.insert(tags.end(), more.begin(), more.end());
  return test::withPlugin(urdf, "finger_mimic", kPlugin, tags);
}

double position(const Robot& robot, const std::string& joint) {
  return robot.body().jointPosition(robot.body().jointIndex(joint));
}

/// Commands the left finger to `target` and steps `seconds`.
void close(Simulation& simulation, Robot& robot, double target, double seconds) {
  ASSERT_TRUE(test::pluginsOf<JointPosition>(robot).at(0)->setTarget("left_finger_joint", target));
  for (int i = 0; i < static_cast<int>(seconds / simulation.stepSize()); ++i) simulation.step();
}

TEST(MimicJoint, OneCommandClosesBothFingersByTheUrdfMimic) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("gripper", test::parseQuietly(gripper(wheel_model), "gripper"), {});
    close(simulation, robot, 0.03, 1.0);
    EXPECT_NEAR(position(robot, "left_finger_joint"), 0.03, 0.002);
    EXPECT_NEAR(position(robot, "right_finger_joint"), position(robot, "left_finger_joint"), 0.001);
    const JointStateSample& states =
        test::latestOf<JointStateSample>(*test::pluginsOf<JointStates>(robot).at(0));
    EXPECT_THAT(states.names, ::testing::ElementsAre("left_finger_joint", "right_finger_joint"));
    EXPECT_NEAR(states.positions.at(1), 0.03, 0.002);
  }
}

TEST(MimicJoint, ThePluginsMultiplierAndOffsetHoldTheFollower) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    const std::string urdf =
        withMimicPlugin(gripperWithoutMimic(wheel_model), {{"multiplier", "0.5"}, {"offset", "0.01"}});
    Robot& robot = simulation.spawn("gripper", test::parseQuietly(urdf, "gripper"), {});
    for (double target : {0.02, 0.04, 0.0}) {
      close(simulation, robot, target, 1.0);
      EXPECT_NEAR(position(robot, "left_finger_joint"), target, 0.002);
      EXPECT_NEAR(position(robot, "right_finger_joint"), 0.5 * position(robot, "left_finger_joint") + 0.01,
                  0.001);
    }
  }
}

TEST(MimicJoint, AFollowerNamedByBothIsCoupledOnceWithThePluginsEffort) {
  Simulation simulation(test::shippedWorld("empty.world"));
  const std::string urdf = withMimicPlugin(gripper("contact"), {{"maxEffort", "4"}});
  Robot& robot = simulation.spawn("gripper", test::parseQuietly(urdf, "gripper"), {});
  const JointSpec::Mimic& mimic = *robot.body().spec().joint("right_finger_joint")->mimic;
  EXPECT_THAT(mimic.source, HasSubstr("finger_mimic"));
  EXPECT_EQ(mimic.max_effort, 4);
  close(simulation, robot, 0.02, 1.0);
  // Pushing the follower with less than the coupling's 4 N leaves it where the leader says; with more, the
  // coupling gives and the follower runs to its upper limit (the leader's motor holds 20 N).
  const int follower = robot.body().jointIndex("right_finger_joint");
  for (const auto& [push, moved] : {std::pair{2.0, false}, std::pair{8.0, true}}) {
    SCOPED_TRACE(push);
    for (int i = 0; i < 500; ++i) {
      robot.body().setJointEffort(follower, push);
      simulation.step();
    }
    if (moved) {
      EXPECT_NEAR(position(robot, "right_finger_joint"), 0.04, 0.002);
    } else {
      EXPECT_NEAR(position(robot, "right_finger_joint"), 0.02, 0.001);
    }
    EXPECT_NEAR(position(robot, "left_finger_joint"), 0.02, 0.002);
  }
}

TEST(MimicJoint, CouplingsThatCannotBeSimulatedAreSkippedWithAWarning) {
  std::vector<std::string> warnings;
  std::string urdf =
      test::replaceAfter(gripper("contact"), "<mimic joint=", "left_finger_joint", "left_fniger_joint");
  urdf = test::withPlugin(urdf, "ghost", kPlugin, {{"joint", "left_finger_joint"}, {"mimicJoint", "thumb"}});
  const ModelSpec model = parseModel(urdf, "gripper", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_FALSE(model.joint("right_finger_joint")->mimic);
  EXPECT_THAT(warnings,
              ::testing::Contains(HasSubstr("<mimic> of [left_fniger_joint]: [left_fniger_joint] is not a "
                                            "moving joint (did you mean [left_finger_joint]?)")));
  EXPECT_THAT(warnings, ::testing::Contains(HasSubstr("<mimicJoint> [thumb] is not a moving joint")));
}

TEST(MimicJoint, RosControlLeavesAFollowerToItsCoupling) {
  std::string urdf = test::editUrdf(gripper("contact"), [](tinyxml2::XMLElement& robot) {
    for (const char* joint : {"left_finger_joint", "right_finger_joint"}) {
      auto* transmission = robot.InsertNewChildElement("transmission");
      transmission->SetAttribute("name", (std::string(joint) + "_transmission").c_str());
      transmission->InsertNewChildElement("type")->SetText("transmission_interface/SimpleTransmission");
      auto* driven = transmission->InsertNewChildElement("joint");
      driven->SetAttribute("name", joint);
      driven->InsertNewChildElement("hardwareInterface")
          ->SetText("hardware_interface/PositionJointInterface");
      auto* actuator = transmission->InsertNewChildElement("actuator");
      actuator->SetAttribute("name", (std::string(joint) + "_motor").c_str());
      actuator->InsertNewChildElement("mechanicalReduction")->SetText("1");
    }
    robot.InsertNewChildElement("gazebo")->InsertNewChildElement("plugin")->SetAttribute(
        "filename", "libgazebo_ros_control.so");
  });
  Simulation simulation(test::shippedWorld("empty.world"));
  std::vector<std::string> warnings;
  simulation.spawn("gripper", parseModel(urdf, "gripper", PackageResolver::fromEnvironment(), &warnings), {},
                   &warnings);
  EXPECT_THAT(warnings,
              ::testing::Contains(HasSubstr(
                  "joint [right_finger_joint] follows [left_finger_joint] by <mimic>: ros_control does "
                  "not drive it")));
  EXPECT_THAT(warnings, ::testing::Not(::testing::Contains(HasSubstr("joint [left_finger_joint] follows"))));
}

}  // namespace
}  // namespace bullet_sim
