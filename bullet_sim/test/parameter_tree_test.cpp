// The parameter tree that controllers will read, on a control.yaml in Husky's form.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/plugins/parameter_tree.h"

namespace bullet_sim {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

const char kControl[] = R"(husky_joint_publisher:
  type: "joint_state_controller/JointStateController"
  publish_rate: 50
husky_velocity_controller:
  type: "diff_drive_controller/DiffDriveController"
  left_wheel: ['front_left_wheel', 'rear_left_wheel']
  right_wheel: 'front_right_wheel'
  publish_rate: 50
  pose_covariance_diagonal: [0.001, 0.001, 1000000.0, 1000000.0, 1000000.0, 0.03]
  wheel_separation_multiplier: 1.875
  enable_odom_tf: false
  linear:
    x:
      has_velocity_limits: true
      max_velocity: 1.0
)";

TEST(ParameterTree, ReadsAControllersParametersByPath) {
  const ParameterTree tree = ParameterTree::fromYaml(kControl, "control.yaml");
  EXPECT_THAT(tree.keys(), ElementsAre("husky_joint_publisher", "husky_velocity_controller"));
  const ParameterTree drive = tree.at("husky_velocity_controller");
  EXPECT_EQ(drive.text("type", ""), "diff_drive_controller/DiffDriveController");
  EXPECT_THAT(drive.texts("left_wheel"), ElementsAre("front_left_wheel", "rear_left_wheel"));
  EXPECT_THAT(drive.texts("right_wheel"), ElementsAre("front_right_wheel"));
  EXPECT_DOUBLE_EQ(drive.number("wheel_separation_multiplier", 1.0), 1.875);
  EXPECT_DOUBLE_EQ(drive.number("linear/x/max_velocity", 0.0), 1.0);
  EXPECT_TRUE(drive.flag("linear/x/has_velocity_limits", false));
  EXPECT_FALSE(drive.flag("enable_odom_tf", true));
  EXPECT_THAT(drive.numbers("pose_covariance_diagonal"), ElementsAre(0.001, 0.001, 1e6, 1e6, 1e6, 0.03));
  EXPECT_DOUBLE_EQ(tree.number("husky_joint_publisher/publish_rate", 0), 50);
}

TEST(ParameterTree, AnAbsentParameterGivesItsDefault) {
  const ParameterTree tree = ParameterTree::fromYaml(kControl, "control.yaml");
  EXPECT_FALSE(tree.has("husky_velocity_controller/cmd_vel_timeout"));
  EXPECT_DOUBLE_EQ(tree.number("husky_velocity_controller/cmd_vel_timeout", 0.5), 0.5);
  EXPECT_TRUE(tree.at("no_such_controller").keys().empty());
  EXPECT_TRUE(ParameterTree().texts("anything").empty());
  // Looking up does not add what it looked for.
  EXPECT_FALSE(tree.has("husky_velocity_controller/cmd_vel_timeout"));
}

TEST(ParameterTree, AValueOfTheWrongKindNamesItsPathAndValue) {
  const ParameterTree drive =
      ParameterTree::fromYaml(kControl, "control.yaml").at("husky_velocity_controller");
  try {
    drive.number("type", 0);
    FAIL() << "a text was read as a number";
  } catch (const SpecError& error) {
    EXPECT_THAT(error.what(), HasSubstr("control.yaml"));
    EXPECT_THAT(error.what(), HasSubstr("husky_velocity_controller/type must be a number, not "
                                        "[diff_drive_controller/DiffDriveController]"));
  }
  EXPECT_THROW(drive.flag("linear", false), SpecError);
}

TEST(ParameterTree, ASyntaxErrorNamesTheFileLineAndColumn) {
  try {
    ParameterTree::fromYaml("a: 1\nb: [1, 2\n", "broken.yaml");
    FAIL() << "broken YAML was accepted";
  } catch (const SpecError& error) {
    EXPECT_THAT(error.what(), HasSubstr("broken.yaml"));
    EXPECT_THAT(error.what(), HasSubstr("line "));
  }
}

}  // namespace
}  // namespace bullet_sim
