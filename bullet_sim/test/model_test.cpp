// Loading robot models: one fixture per failure mode, each with the message it must give.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

using test::fixture;
using test::readFile;

/// The message of the SpecError that loading `file` throws, or "" when it loads.
std::string loadError(const std::string& file) {
  try {
    parseModel(readFile(fixture("robots/" + file)), file, PackageResolver::fromEnvironment());
  } catch (const SpecError& e) {
    return e.what();
  }
  return "";
}

/// How many of `messages` hold `text`.
long countContaining(const std::vector<std::string>& messages, const std::string& text) {
  return std::count_if(messages.begin(), messages.end(),
                       [&](const std::string& message) { return message.find(text) != std::string::npos; });
}

TEST(ModelSpec, LoadsTheMinimalRobot) {
  const ModelSpec model = parseModel(readFile(fixture("robots/minimal.urdf")), "minimal.urdf",
                                     PackageResolver::fromEnvironment());
  EXPECT_EQ(model.name, "minimal");
  ASSERT_EQ(model.links.size(), 1u);
  EXPECT_DOUBLE_EQ(model.links[0].inertial->mass, 1.0);
  EXPECT_EQ(model.links[0].collisions[0].shape.type, Shape::Type::kBox);
}

TEST(ModelSpec, MalformedXmlNamesTheLine) {
  const std::string error = loadError("fail_malformed.urdf");
  EXPECT_THAT(error, HasSubstr("fail_malformed.urdf"));
  EXPECT_THAT(error, HasSubstr("line 2:"));  // where <robot> opens
  EXPECT_THAT(error, HasSubstr("closed by a different tag"));
}

TEST(ModelSpec, NonBreakingSpaceIsNamedWithLineAndColumn) {
  const std::string error = loadError("fail_non_breaking_space.urdf");
  EXPECT_THAT(error, HasSubstr("line 3 column 8 holds a non-breaking space (U+00A0"));
}

TEST(ModelSpec, MissingMeshNamesLinkAndUri) {
  const std::string error = loadError("fail_missing_mesh.urdf");
  EXPECT_THAT(error, HasSubstr("link [base_link] <collision>: cannot load mesh"));
  EXPECT_THAT(error, HasSubstr("no_such_mesh.stl"));
  // A visual's missing mesh is a warning: Gazebo loads the robot, and that visual is not drawn.
  std::string urdf = readFile(fixture("robots/fail_missing_mesh.urdf"));
  for (const std::string& element : {std::string("<collision>"), std::string("</collision>")})
    urdf.replace(urdf.find(element), element.size(), element == "<collision>" ? "<visual>" : "</visual>");
  std::vector<std::string> warnings;
  const ModelSpec model = parseModel(urdf, "visual_only", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_TRUE(model.link("base_link")->visuals.empty());
  EXPECT_THAT(warnings, ::testing::ElementsAre(::testing::AllOf(
                            HasSubstr("link [base_link] <visual>: cannot find mesh"),
                            HasSubstr("no_such_mesh.stl"), HasSubstr("that visual is not drawn"))));
}

// An element URDF does not have (OpenManipulator-X's <RefLink/>, a macro called without the xacro: prefix) is
// skipped by urdfdom and Gazebo: one warning per name, with its lines and the fix; an error under
// ~strict_models.
TEST(ModelSpec, AnUnexpandedMacroCallIsSkippedWithTheXacroPrefixSuggested) {
  const std::string urdf = readFile(fixture("robots/unexpanded_gazebo_macro.urdf"));
  const std::string message =
      "lines 19, 20: <RefLink/> is not a URDF element: ignored, as urdfdom and Gazebo ignore it (an error in "
      "urdf_doctor and under ~strict_models); if it is a xacro macro call, write <xacro:RefLink/>";
  std::vector<std::string> warnings;
  const ModelSpec model =
      parseModel(urdf, "unexpanded_gazebo_macro.urdf", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_EQ(countContaining(warnings, "RefLink"), 1);
  EXPECT_THAT(warnings, testing::Contains(HasSubstr(message)));
  EXPECT_DOUBLE_EQ(model.link("link1")->surface.mu1, 1.0);  // the call set nothing
  EXPECT_DOUBLE_EQ(model.link("link2")->surface.mu1, 30.0);  // the expanded block did
  try {
    parseModel(urdf, "unexpanded_gazebo_macro.urdf", PackageResolver::fromEnvironment(), nullptr, Limits(),
               /*strict=*/true);
    FAIL() << "an element URDF does not have was accepted under strict_models";
  } catch (const SpecError& e) {
    EXPECT_THAT(e.what(), HasSubstr(message));
  }
}

// A negative velocity limit (the Robotiq 3F gripper's velocity="-1") is no limit, as in Gazebo, with one
// warning naming the joints.
TEST(ModelSpec, ANegativeVelocityLimitIsNoLimit) {
  std::vector<std::string> warnings;
  const ModelSpec model = parseModel(readFile(fixture("bad_input/velocity_limits.urdf")),
                                     "velocity_limits.urdf", PackageResolver::fromEnvironment(), &warnings);
  for (const char* joint : {"finger_1_joint_1", "finger_2_joint_1"}) {
    EXPECT_EQ(model.joint(joint)->velocity, 0) << joint;  // 0: no limit given
    EXPECT_EQ(model.joint(joint)->effort, 100) << joint;
  }
  EXPECT_EQ(countContaining(warnings, "velocity"), 1);
}

// So is a negative effort limit (SDF enforces neither), with a warning of its own.
TEST(ModelSpec, ANegativeEffortLimitIsNoLimit) {
  std::string urdf = readFile(fixture("bad_input/velocity_limits.urdf"));
  const std::string limited = "effort=\"100\"";
  urdf.replace(urdf.rfind(limited), limited.size(), "effort=\"-1\"");  // finger 2's
  std::vector<std::string> warnings;
  const ModelSpec model =
      parseModel(urdf, "effort_limits.urdf", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_EQ(model.joint("finger_1_joint_1")->effort, 100);
  EXPECT_EQ(model.joint("finger_2_joint_1")->effort, 0);  // 0: no limit given
  EXPECT_THAT(warnings, testing::Contains(HasSubstr(
                            "joint [finger_2_joint_1] <limit effort> is negative: read as no effort limit")));
}

// Gazebo skips a <gazebo reference> block that names nothing without a word: we skip it with a warning that
// suggests the near miss, and refuse it under ~strict_models.
TEST(ModelSpec, GazeboReferenceToMissingLinkIsSkippedWithTheNearMiss) {
  const std::string urdf = readFile(fixture("robots/sensor_missing_link.urdf"));
  const std::string message =
      "<gazebo reference=\"laser_link\"> names no link or joint (did you mean [laser_Link]?): "
      "the block is skipped";
  std::vector<std::string> warnings;
  const ModelSpec model =
      parseModel(urdf, "sensor_missing_link.urdf", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_TRUE(model.plugins.empty());  // the block's lidar is not there
  EXPECT_THAT(warnings, testing::Contains(HasSubstr(message)));
  try {
    parseModel(urdf, "sensor_missing_link.urdf", PackageResolver::fromEnvironment(), nullptr, Limits(),
               /*strict=*/true);
    FAIL() << "a dangling <gazebo reference> was accepted under strict_models";
  } catch (const SpecError& e) {
    EXPECT_THAT(e.what(), HasSubstr(message));
  }
}

TEST(ModelSpec, ReportsEveryProblemOfAFileAtOnce) {
  const std::string error = loadError("fail_two_problems.urdf");
  EXPECT_THAT(error, HasSubstr("2 problems"));
  EXPECT_THAT(error, HasSubstr("mass -1 kg is not positive"));
  EXPECT_THAT(error, HasSubstr("no_such_mesh.stl"));
}

TEST(ModelSpec, UnknownJointInAPluginFailsTheLoadWithASuggestion) {
  Simulation simulation(test::shippedWorld("empty.world"));
  try {  // refused at load, with the file's other problems
    simulation.spawn("robot",
                     parseModel(readFile(fixture("robots/fail_unknown_plugin_joint.urdf")),
                                "fail_unknown_plugin_joint.urdf", PackageResolver::fromEnvironment()),
                     {});
    FAIL() << "spawn accepted a drive naming a missing joint";
  } catch (const SpecError& e) {
    EXPECT_THAT(std::string(e.what()),
                HasSubstr("plugin [drive] names joint [right_whel_joint], which does not "
                          "exist (did you mean [right_wheel_joint]?)"));
  }
  EXPECT_TRUE(simulation.robotNames().empty()) << "a refused robot leaves nothing behind";
  simulation.step();
}

TEST(ModelSpec, SpawnRefusesADuplicateName) {
  Simulation simulation(test::shippedWorld("empty.world"));
  const auto model = [] {
    return parseModel(readFile(fixture("robots/minimal.urdf")), "minimal.urdf",
                      PackageResolver::fromEnvironment());
  };
  simulation.spawn("robot", model(), {});
  try {
    simulation.spawn("robot", model(), {.x = 2});
    FAIL() << "two robots share a name";
  } catch (const SpecError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("a robot named [robot] already exists"));
  }
  EXPECT_EQ(simulation.robotNames().size(), 1u);
}

TEST(ModelSpec, ReadsTransmissionsAsRosControlDoes) {
  std::vector<std::string> warnings;
  const ModelSpec model = parseModel(readFile(fixture("robots/transmissions.urdf")), "transmissions.urdf",
                                     PackageResolver::fromEnvironment(), &warnings);
  // Both spellings of the interface are kept as written; the two that ros_control skips are not there.
  ASSERT_EQ(model.transmissions.size(), 3u);
  const TransmissionSpec& left = model.transmissions[0];
  EXPECT_EQ(left.name, "left_wheel_trans");
  EXPECT_EQ(left.type, "transmission_interface/SimpleTransmission");
  ASSERT_EQ(left.joints.size(), 1u);
  EXPECT_EQ(left.joints[0].name, "left_wheel_joint");
  EXPECT_THAT(left.joints[0].hardware_interfaces,
              ::testing::ElementsAre("hardware_interface/VelocityJointInterface"));
  ASSERT_EQ(left.actuators.size(), 1u);
  EXPECT_EQ(left.actuators[0].name, "left_wheel_motor");
  EXPECT_THAT(model.transmissions[1].joints[0].hardware_interfaces,
              ::testing::ElementsAre("EffortJointInterface"));
  EXPECT_DOUBLE_EQ(model.transmissions[1].actuators[0].mechanical_reduction, 30);
  EXPECT_EQ(model.transmissions[2].name, "odd_trans");
  EXPECT_DOUBLE_EQ(model.transmissions[2].actuators[0].mechanical_reduction, 1);

  std::string all;
  for (const auto& warning : warnings) all += warning + "\n";
  EXPECT_THAT(all, HasSubstr("transmission [untyped_trans] (line 37) has no <type>"));
  EXPECT_THAT(all, HasSubstr("transmission [old_style_trans] (line 41) joint [right_wheel_joint] has no "
                             "<hardwareInterface>, which ros_control reads inside <joint>"));
  EXPECT_THAT(all, HasSubstr("transmission [old_style_trans] (line 41) has no <joint> with a "
                             "<hardwareInterface>: ros_control skips it"));
  EXPECT_THAT(all, HasSubstr("actuator [odd_motor] <mechanicalReduction> must be a non-zero number, not "
                             "[fast]: 1 is used"));
  EXPECT_THAT(all, HasSubstr("(line 48) <actuator name=\"odd_motor\"> <gearRatio> is not a tag"));
  EXPECT_THAT(all,
              HasSubstr("<transmission>s [left_wheel_trans], [right_wheel_trans] and [odd_trans] are not "
                        "used: only libgazebo_ros_control.so reads transmissions"));
  EXPECT_EQ(warnings.size(), 6u) << all;
}

TEST(Diagnostics, SuggestsNearMissesOnly) {
  EXPECT_EQ(closestName("laser_link", {"base_link", "laser_Link"}), "laser_Link");
  EXPECT_EQ(closestName("front_left_jiont", {"front_left_joint", "front_right_joint"}), "front_left_joint");
  EXPECT_EQ(closestName("camera", {"base_link", "laser_Link"}), "");
}

}  // namespace
}  // namespace bullet_sim
