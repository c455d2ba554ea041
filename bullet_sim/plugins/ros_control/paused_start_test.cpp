// A paused spawn with initial joint positions, in-process: spawn_model -J ... -unpause sets the joints with
// set_model_configuration while the world has not stepped, and the spawner loads and starts the controllers
// meanwhile, in either order. A controller started before the unpause holds the joints where -J put them: no
// joint moves more than 0.01 rad from there once the world runs (trajectory_arm.urdf, joints about vertical
// axes, so only a controller can move them).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/simulation/world_api.h"
#include "plugins/ros_control/joint_trajectory_controller.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
using Action = FollowJointTrajectoryAction;

const std::map<std::string, double> kInitial = {{"shoulder", 1.2}, {"wrist", -0.7}};

/// The controllers' parameters under /arm: the three variants Kortex's, UR's and a user's arms use.
const std::string kYaml = R"(arm:
  position_trajectory:
    type: position_controllers/JointTrajectoryController
    joints: [shoulder, wrist]
  effort_trajectory:
    type: effort_controllers/JointTrajectoryController
    joints: [shoulder, wrist]
    gains:
      shoulder: {p: 400, d: 40, i: 0}
      wrist: {p: 100, d: 10, i: 0}
  group_position:
    type: position_controllers/JointGroupPositionController
    joints: [shoulder, wrist]
)";

/// trajectory_arm.urdf spawned as "arm" with its transmissions on `interface`, in a world that has not
/// stepped.
class PausedArm {
 public:
  explicit PausedArm(const std::string& interface)
      : parameters_(ParameterTree::fromYaml(kYaml, "control.yaml")),
        simulation_(test::shippedWorld("empty.world"), options()),
        world_(simulation_) {
    robot_ = &simulation_.spawn("arm", test::trajectoryArm(interface), SpawnPose{});
    plugin_ = test::pluginsOf<RosControl>(*robot_).at(0);
  }

  SimulationOptions options() {
    SimulationOptions options;
    options.parameters = &parameters_;
    return options;
  }
  /// load_controller and switch_controller (STRICT) as the spawner calls them.
  void startController(const std::string& name) {
    ASSERT_EQ(plugin_->controllerManager().load(name, nullptr), "");
    SwitchControllerRequest start;
    start.start = {name};
    start.strictness = SwitchControllerRequest::kStrict;
    ASSERT_EQ(plugin_->switchControllers(start, nullptr), "");
  }
  /// set_model_configuration with kInitial: its note.
  std::string placeJoints() { return world_.setModelConfiguration("arm", kInitial); }
  double position(const std::string& joint) const {
    return robot_->body().jointPosition(robot_->body().jointIndex(joint));
  }
  /// The largest distance of a joint from kInitial over `seconds` of running.
  double worstDrift(double seconds) {
    double worst = 0;
    for (long k = std::lround(seconds / simulation_.stepSize()); k > 0; --k) {
      simulation_.step();
      for (const auto& [joint, initial] : kInitial)
        worst = std::max(worst, std::abs(position(joint) - initial));
    }
    return worst;
  }
  ControllerManager& manager() { return plugin_->controllerManager(); }
  double time() const { return simulation_.time(); }

 private:
  TreeParameters parameters_;
  Simulation simulation_;
  WorldApi world_;
  Robot* robot_ = nullptr;
  RosControl* plugin_ = nullptr;
};

struct Variant {
  const char* interface;
  const char* controller;
};

class PausedSpawn : public ::testing::TestWithParam<Variant> {};

TEST_P(PausedSpawn, AControllerStartedBeforeTheJointsAreSetHoldsThem) {
  PausedArm arm(GetParam().interface);
  arm.startController(GetParam().controller);
  EXPECT_EQ(arm.placeJoints(), "");
  for (const auto& [joint, initial] : kInitial) EXPECT_DOUBLE_EQ(arm.position(joint), initial) << joint;
  EXPECT_LT(arm.worstDrift(1.0), 0.01);
}

TEST_P(PausedSpawn, AControllerStartedAfterTheJointsAreSetHoldsThem) {
  PausedArm arm(GetParam().interface);
  EXPECT_EQ(arm.placeJoints(), "");
  arm.startController(GetParam().controller);
  EXPECT_LT(arm.worstDrift(1.0), 0.01);
}

INSTANTIATE_TEST_SUITE_P(Controllers, PausedSpawn,
                         ::testing::Values(Variant{"PositionJointInterface", "position_trajectory"},
                                           Variant{"EffortJointInterface", "effort_trajectory"},
                                           Variant{"PositionJointInterface", "group_position"}),
                         [](const auto& info) { return std::string(info.param.controller); });

// Once a controller has updated, it holds its own point: set_model_configuration then moves the joints only
// until the controller pulls them back, as in Gazebo.
TEST(PausedSpawnRunning, AControllerThatHasUpdatedKeepsItsHoldPoint) {
  PausedArm arm("PositionJointInterface");
  arm.startController("position_trajectory");
  arm.worstDrift(0.01);
  EXPECT_EQ(arm.placeJoints(), "");
  arm.worstDrift(3.0);
  EXPECT_NEAR(arm.position("shoulder"), 0, 0.01);
  EXPECT_NEAR(arm.position("wrist"), 0, 0.01);
}

// A goal sent before the first update is canceled when the joints are set under it, with one warning.
TEST(PausedSpawnRunning, SettingTheJointsUnderAGoalBeforeTheFirstUpdateCancelsItWithAWarning) {
  PausedArm arm("PositionJointInterface");
  arm.startController("position_trajectory");
  auto& controller = dynamic_cast<JointTrajectoryController&>(*arm.manager().find("position_trajectory"));
  const auto& action = std::get<ActionHandlers<Action>>(controller.ports().actions.at(0).sink);
  Action::Goal goal;
  goal.trajectory.joint_names = {"shoulder", "wrist"};
  goal.trajectory.points.push_back({{0.3, 0.3}, {}, {}, {}, 1.0});
  ASSERT_TRUE(action.goal(7, goal, arm.time()).accepted);
  const std::string note = arm.placeJoints();
  EXPECT_THAT(note, HasSubstr("controller [position_trajectory] had not updated since it started"));
  EXPECT_THAT(note, HasSubstr("follow_joint_trajectory goal 7 is canceled"));
  const auto reports = action.reports->take();
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(*reports[0].end, GoalEnd::kCanceled);
  EXPECT_EQ(controller.activeGoal(), 0u);
  EXPECT_LT(arm.worstDrift(0.5), 0.01);
}

}  // namespace
}  // namespace bullet_sim
