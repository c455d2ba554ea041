// The joint trajectory controllers in the world, in-process: a two-link arm (trajectory_arm.urdf) follows
// trajectories given through the follow_joint_trajectory action and the command topic, with their tolerances,
// replacement, cancelling, query_state and state, on each of the three interfaces; an obstacle, a joint limit
// and tight tolerances abort goals with ros_controllers' error codes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "plugins/ros_control/joint_trajectory_controller.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
using ::testing::IsEmpty;
using Action = FollowJointTrajectoryAction;
using Report = GoalReports<Action>::Report;

/// The position controller's parameters, as a user's control.yaml gives them.
const std::string kPositionYaml = R"(arm_controller:
  type: position_controllers/JointTrajectoryController
  joints: [shoulder, wrist]
  constraints:
    goal_time: 0.5
    stopped_velocity_tolerance: 0.05
    shoulder: {trajectory: 0.05, goal: 0.01}
    wrist: {trajectory: 0.05, goal: 0.01}
)";

/// The closed-loop variants' parameters: `type` with PID gains per joint, and `feed_forward` on both.
std::string closedLoopYaml(const std::string& type, const std::string& shoulder_gains,
                           const std::string& wrist_gains, double feed_forward) {
  return "arm_controller:\n  type: " + type +
         "\n  joints: [shoulder, wrist]\n  constraints:\n    goal_time: 0.5\n    stopped_velocity_tolerance: "
         "0.05\n"
         "    shoulder: {trajectory: 0.05, goal: 0.01}\n    wrist: {trajectory: 0.05, goal: 0.01}\n"
         "  gains:\n    shoulder: " +
         shoulder_gains + "\n    wrist: " + wrist_gains +
         "\n  velocity_ff: {shoulder: " + std::to_string(feed_forward) +
         ", wrist: " + std::to_string(feed_forward) + "}\n";
}

/// `yaml` under the robot's namespace, /arm, as `rosparam load` puts it in a <group ns="arm">.
std::string inArmNamespace(const std::string& yaml) {
  std::string nested = "arm:\n";
  std::istringstream lines(yaml);
  for (std::string line; std::getline(lines, line);) nested += "  " + line + "\n";
  return nested;
}

/// trajectory_arm.urdf with its transmissions on `interface`, spawned as "arm" in `world` with `yaml`.
class Arm {
 public:
  explicit Arm(const std::string& yaml, const std::string& interface = "PositionJointInterface",
               const WorldSpec& world = test::shippedWorld("empty.world"))
      : parameters_(ParameterTree::fromYaml(inArmNamespace(yaml), "control.yaml")),
        simulation_(world, options()) {
    robot_ = &simulation_.spawn("arm", test::trajectoryArm(interface), SpawnPose{});
    manager_ = &test::pluginsOf<RosControl>(*robot_).at(0)->controllerManager();
  }

  SimulationOptions options() {
    SimulationOptions options;
    options.parameters = &parameters_;
    return options;
  }
  void load() { ASSERT_EQ(manager_->load("arm_controller", nullptr), ""); }
  /// Starts the controller (loading it first when it is not), and lets the arm settle for 0.1 s.
  void start() {
    if (!manager_->find("arm_controller")) load();
    SwitchControllerRequest start;
    start.start = {"arm_controller"};
    ASSERT_EQ(manager_->switchControllers(start, simulation_.time(), nullptr), "");
    stepFor(0.1);
  }
  JointTrajectoryController& controller() {
    return dynamic_cast<JointTrajectoryController&>(*manager_->find("arm_controller"));
  }
  const ActionHandlers<Action>& action() {
    return std::get<ActionHandlers<Action>>(controller().ports().actions.at(0).sink);
  }
  /// Sends a goal as the node does, numbering it; its decision.
  GoalDecision<Action> send(const Action::Goal& goal) {
    return action().goal(++last_goal_, goal, simulation_.time());
  }
  GoalId lastGoal() const { return last_goal_; }
  /// The command topic's input.
  std::string command(const JointTrajectory& trajectory) {
    return std::get<InputHandler<JointTrajectory>>(controller().ports().inputs.at(0).sink)(
        trajectory, simulation_.time());
  }
  /// One step; what the controller reported in it is appended to reports(), and its state to states().
  void step() {
    simulation_.step();
    for (auto& report : action().reports->take()) reports_.push_back(report);
    states_.push_back(controller().state());
  }
  void stepFor(double seconds) {
    for (long k = std::lround(seconds / simulation_.stepSize()); k > 0; --k) step();
  }
  /// Steps until goal `goal` ends (at most `seconds`); its end report.
  std::optional<Report> runUntilEnd(GoalId goal, double seconds) {
    std::optional<Report> end;
    test::stepUntil(
        simulation_,
        [&] {
          for (auto& report : action().reports->take()) reports_.push_back(report);
          states_.push_back(controller().state());
          for (const auto& report : reports_)
            if (report.goal == goal && report.end) end = report;
          return end.has_value();
        },
        seconds, "the end of goal " + std::to_string(goal));
    return end;
  }
  double position(const std::string& joint) const {
    return robot_->body().jointPosition(robot_->body().jointIndex(joint));
  }
  double time() const { return simulation_.time(); }
  double stepSize() const { return simulation_.stepSize(); }
  const std::vector<Report>& reports() const { return reports_; }
  std::vector<JointTrajectoryControllerState>& states() { return states_; }
  ControllerManager& manager() { return *manager_; }

 private:
  TreeParameters parameters_;
  Simulation simulation_;
  Robot* robot_ = nullptr;
  ControllerManager* manager_ = nullptr;
  GoalId last_goal_ = 0;
  std::vector<Report> reports_;
  std::vector<JointTrajectoryControllerState> states_;
};

/// Waypoints for shoulder and wrist: positions and (when given) velocities at `times` [s].
JointTrajectory waypoints(const std::vector<std::vector<double>>& positions, const std::vector<double>& times,
                          const std::vector<std::vector<double>>& velocities = {}) {
  JointTrajectory trajectory;
  trajectory.joint_names = {"shoulder", "wrist"};
  for (size_t k = 0; k < positions.size(); ++k) {
    trajectory.points.push_back(
        {positions[k], velocities.empty() ? std::vector<double>{} : velocities[k], {}, {}, times[k]});
  }
  return trajectory;
}

Action::Goal goalOf(const JointTrajectory& trajectory) {
  Action::Goal goal;
  goal.trajectory = trajectory;
  return goal;
}

/// The three waypoints of the tests: out, across and back, with velocities through the middle one.
const JointTrajectory kThreeWaypoints =
    waypoints({{0.6, -0.8}, {1.2, 0.4}, {0.3, 0.0}}, {1.0, 2.0, 3.0}, {{0.6, 0.0}, {0.0, 0.8}, {0.0, 0.0}});

/// Follows kThreeWaypoints through the action: each waypoint is reached within the goal tolerance (0.01) at
/// its time, the error stays within the path tolerance (0.05) all the way, and the goal succeeds.
void followThreeWaypoints(Arm& arm, double goal_tolerance) {
  ASSERT_TRUE(arm.send(goalOf(kThreeWaypoints)).accepted);
  const double start = arm.time() + arm.stepSize();  // the trajectory starts at the next update
  const GoalId goal = arm.lastGoal();
  const auto end = arm.runUntilEnd(goal, 4.0);
  ASSERT_TRUE(end);
  EXPECT_EQ(*end->end, GoalEnd::kSucceeded);
  EXPECT_EQ(end->result.error_code, Action::Result::kSuccessful);
  size_t checked = 0;
  double worst = 0;
  for (const auto& state : arm.states()) {
    if (state.stamp < start) continue;
    for (double error : state.error.positions) worst = std::max(worst, std::abs(error));
    for (size_t k = 0; k < kThreeWaypoints.points.size(); ++k) {
      if (std::abs(state.stamp - (start + kThreeWaypoints.points[k].time_from_start)) > arm.stepSize() / 2)
        continue;
      ++checked;
      for (size_t j = 0; j < 2; ++j) {
        EXPECT_NEAR(state.desired.positions[j], kThreeWaypoints.points[k].positions[j], 1e-9);
        EXPECT_NEAR(state.actual.positions[j], kThreeWaypoints.points[k].positions[j], goal_tolerance)
            << "waypoint " << k << " joint " << j;
      }
    }
  }
  EXPECT_EQ(checked, 3u);
  EXPECT_LT(worst, 0.05) << "the largest position error on the way";
  // Feedback came while it ran, at the action monitor's 20 Hz.
  const auto feedback = std::count_if(arm.reports().begin(), arm.reports().end(), [&](const Report& report) {
    return report.goal == goal && !report.end;
  });
  EXPECT_GE(feedback, 1);
}

TEST(JointTrajectoryController, PositionJointsReachEachOfThreeWaypointsAtItsTime) {
  Arm arm(kPositionYaml);
  arm.start();
  followThreeWaypoints(arm, 0.01);
  EXPECT_NEAR(arm.position("shoulder"), 0.3, 0.01);
  EXPECT_NEAR(arm.position("wrist"), 0.0, 0.01);
}

TEST(JointTrajectoryController, VelocityJointsFollowThroughTheirPidAndFeedForward) {
  Arm arm(closedLoopYaml("velocity_controllers/JointTrajectoryController", "{p: 50}", "{p: 50}", 1.0),
          "VelocityJointInterface");
  arm.start();
  followThreeWaypoints(arm, 0.01);
}

TEST(JointTrajectoryController, EffortJointsFollowThroughTheirPid) {
  // PD loops near critical damping for the arm's inertias about the joints (about 0.6 and 0.03 kg m^2).
  Arm arm(closedLoopYaml("effort_controllers/JointTrajectoryController",
                         "{p: 2000, d: 60, i: 200, i_clamp: 20}", "{p: 500, d: 7, i: 50, i_clamp: 5}", 0.0),
          "EffortJointInterface");
  arm.start();
  followThreeWaypoints(arm, 0.01);
}

/// The time of the first state after `time` in which the shoulder's desired position changes by more than
/// `jump` from one update to the next; NAN when it never does.
double jumpAfter(const std::vector<JointTrajectoryControllerState>& states, double time, double jump) {
  for (size_t k = 1; k < states.size(); ++k) {
    if (states[k].stamp > time &&
        std::abs(states[k].desired.positions[0] - states[k - 1].desired.positions[0]) > jump)
      return states[k].stamp;
  }
  return NAN;
}

TEST(JointTrajectoryController, TooTightAPathToleranceAbortsTheGoal) {
  Arm arm(kPositionYaml);
  arm.start();
  Action::Goal goal = goalOf(kThreeWaypoints);
  goal.path_tolerance = {{"shoulder", 1e-4, 0, 0}};  // the position motor lags by more on the way
  ASSERT_TRUE(arm.send(goal).accepted);
  const auto end = arm.runUntilEnd(arm.lastGoal(), 1.0);
  ASSERT_TRUE(end);
  EXPECT_EQ(*end->end, GoalEnd::kAborted);
  EXPECT_EQ(end->result.error_code, Action::Result::kPathToleranceViolated);
  EXPECT_THAT(end->result.error_string, HasSubstr("shoulder path error"));
}

TEST(JointTrajectoryController, AJointHeldAtItsLimitMissesTheGoalAndAbortsAfterGoalTime) {
  // The shoulder's limit is 3 rad; asked for 3.4 at 2 s, it stops at 3. Without a path tolerance, the goal
  // aborts once goal_time (0.5 s) has passed after the end.
  Arm arm(kPositionYaml);
  arm.start();
  Action::Goal goal = goalOf(waypoints({{3.4, 0.0}}, {2.0}));
  goal.path_tolerance = {{"shoulder", -1, 0, 0}};
  ASSERT_TRUE(arm.send(goal).accepted);
  const double end_time = arm.time() + arm.stepSize() + 2.0;
  const auto end = arm.runUntilEnd(arm.lastGoal(), 3.0);
  ASSERT_TRUE(end);
  EXPECT_EQ(end->result.error_code, Action::Result::kGoalToleranceViolated);
  EXPECT_THAT(end->result.error_string, HasSubstr("shoulder goal error 0.4"));
  EXPECT_NEAR(arm.time(), end_time + 0.5, 2 * arm.stepSize());
  EXPECT_NEAR(arm.position("shoulder"), 3.0, 1e-3);
}

TEST(JointTrajectoryController, AnArmHeldByAnObstacleAbortsItsGoal) {
  // arm_post.world: the post stops the straight arm at pi/2 - asin(0.07 / 0.65) = 1.463 rad of its way to 2.
  Arm arm(kPositionYaml, "PositionJointInterface",
          loadWorld(test::fixture("worlds/arm_post.world"), PackageResolver::fromEnvironment(), nullptr));
  arm.start();
  ASSERT_TRUE(arm.send(goalOf(waypoints({{2.0, 0.0}}, {2.0}))).accepted);
  const auto end = arm.runUntilEnd(arm.lastGoal(), 2.0);
  ASSERT_TRUE(end);
  EXPECT_EQ(end->result.error_code, Action::Result::kPathToleranceViolated);
  EXPECT_NEAR(arm.position("shoulder"), M_PI / 2 - std::asin(0.07 / 0.65), 0.01);
}

TEST(JointTrajectoryController, ANewGoalReplacesTheRunningOneMidWay) {
  Arm arm(kPositionYaml);
  arm.start();
  ASSERT_TRUE(arm.send(goalOf(waypoints({{1.2, 0.0}}, {2.0}))).accepted);
  const GoalId first = arm.lastGoal();
  arm.stepFor(1.0);  // half way: the shoulder at 0.6, moving at 0.6 rad/s
  const double handover = arm.time() + arm.stepSize();
  ASSERT_TRUE(arm.send(goalOf(waypoints({{-0.6, 0.5}}, {1.0}))).accepted);
  ASSERT_FALSE(arm.reports().empty());
  const auto preempted = arm.action().reports->take();
  ASSERT_EQ(preempted.size(), 1u);
  EXPECT_EQ(preempted[0].goal, first);
  EXPECT_EQ(*preempted[0].end, GoalEnd::kCanceled);
  const auto end = arm.runUntilEnd(arm.lastGoal(), 2.0);
  ASSERT_TRUE(end);
  EXPECT_EQ(*end->end, GoalEnd::kSucceeded);
  EXPECT_NEAR(arm.position("shoulder"), -0.6, 0.01);
  EXPECT_NEAR(arm.position("wrist"), 0.5, 0.01);
  // The new trajectory leads on from where the old one was: the desired position moves at most 1.2 rad/s.
  EXPECT_TRUE(std::isnan(jumpAfter(arm.states(), handover - 0.5, 1.2 * arm.stepSize() + 1e-9)));
}

TEST(JointTrajectoryController, ACommandOnTheTopicReplacesTheTrajectoryAndPreemptsTheGoal) {
  Arm arm(kPositionYaml);
  arm.start();
  ASSERT_TRUE(arm.send(goalOf(waypoints({{1.2, 0.0}}, {2.0}))).accepted);
  arm.stepFor(0.5);
  EXPECT_EQ(arm.command(waypoints({{0.0, -0.4}}, {0.5})), "");
  const auto preempted = arm.action().reports->take();
  ASSERT_EQ(preempted.size(), 1u);
  EXPECT_EQ(*preempted[0].end, GoalEnd::kCanceled);
  EXPECT_EQ(arm.controller().activeGoal(), 0u);
  arm.stepFor(1.0);
  EXPECT_NEAR(arm.position("shoulder"), 0.0, 0.01);
  EXPECT_NEAR(arm.position("wrist"), -0.4, 0.01);
  EXPECT_THAT(arm.command(waypoints({{0.0}}, {0.5})), HasSubstr("1 positions for 2 joints"));
}

TEST(JointTrajectoryController, CancellingTheGoalHoldsTheArmWhereItIs) {
  Arm arm(kPositionYaml);
  arm.start();
  ASSERT_TRUE(arm.send(goalOf(waypoints({{1.2, 0.0}}, {2.0}))).accepted);
  arm.stepFor(1.0);
  arm.action().cancel(arm.lastGoal(), arm.time());
  const auto canceled = arm.action().reports->take();
  ASSERT_EQ(canceled.size(), 1u);
  EXPECT_EQ(*canceled[0].end, GoalEnd::kCanceled);
  const double held = arm.states().back().actual.positions[0];  // where the last update saw it
  arm.stepFor(0.5);
  EXPECT_NEAR(arm.states().back().desired.positions[0], held, 1e-9);
  EXPECT_NEAR(arm.position("shoulder"), held, 0.002);
}

TEST(JointTrajectoryController, WithAStopDurationACancelRampsDownToRest) {
  // stop_trajectory_duration 0.5 s: from 0.6 rad/s the desired motion comes to rest 0.6 * 0.5 * 5/8 rad on.
  Arm arm(kPositionYaml + "  stop_trajectory_duration: 0.5\n");
  arm.start();
  ASSERT_TRUE(arm.send(goalOf(waypoints({{1.2, 0.0}}, {2.0}))).accepted);
  arm.stepFor(1.0);
  const double desired = arm.states().back().desired.positions[0];
  arm.action().cancel(arm.lastGoal(), arm.time());
  arm.stepFor(0.6);
  const auto& state = arm.states().back();
  EXPECT_NEAR(state.desired.positions[0], desired + 0.6 * 0.5 * 5 / 8, 1e-6);
  EXPECT_NEAR(state.desired.velocities[0], 0, 1e-9);
}

TEST(JointTrajectoryController, QueryStateSamplesTheTrajectory) {
  Arm arm(kPositionYaml);
  arm.load();
  QueryTrajectoryStateRequest::Reply reply;
  const auto query = [&](double time) {
    reply = {};
    return std::get<ServiceHandler<QueryTrajectoryStateRequest>>(
        arm.controller().ports().services.at(0).handler)({time}, reply);
  };
  EXPECT_THAT(query(0), HasSubstr("is not running"));
  arm.stepFor(0.5);
  arm.start();  // at t = 0.5 s, where the trajectory begins
  ASSERT_TRUE(arm.send(goalOf(kThreeWaypoints)).accepted);
  const double start = arm.time() + arm.stepSize();
  ASSERT_EQ(query(start + 1.0), "");
  EXPECT_EQ(reply.name, (std::vector<std::string>{"shoulder", "wrist"}));
  EXPECT_NEAR(reply.position[0], 0.6, 1e-9);
  EXPECT_NEAR(reply.position[1], -0.8, 1e-9);
  EXPECT_NEAR(reply.velocity[0], 0.6, 1e-9);
  ASSERT_EQ(query(start + 2.5), "");
  EXPECT_NEAR(reply.position[0], (1.2 + 0.3) / 2, 1e-9);  // the cubic from rest to rest, half way
  EXPECT_THAT(query(0.2), HasSubstr("precedes the trajectory's start"));
}

TEST(JointTrajectoryController, PublishesItsStateAtStatePublishRate) {
  Arm arm(kPositionYaml + "  state_publish_rate: 25\n");
  arm.start();
  const auto& stream =
      *std::get<const Stream<JointTrajectoryControllerState>*>(arm.controller().ports().outputs.at(0).stream);
  const uint64_t before = stream.count();
  arm.stepFor(2.0);
  EXPECT_NEAR(static_cast<double>(stream.count() - before), 50, 1);
  EXPECT_EQ(stream.latest().joint_names, (std::vector<std::string>{"shoulder", "wrist"}));
  EXPECT_EQ(stream.latest().desired.accelerations.size(), 2u);
  Arm quiet(kPositionYaml + "  state_publish_rate: 0\n");
  quiet.start();
  EXPECT_EQ(
      std::get<const Stream<JointTrajectoryControllerState>*>(quiet.controller().ports().outputs.at(0).stream)
          ->count(),
      0u);
}

TEST(JointTrajectoryController, GoalsItCannotFollowAreRejectedWithRosControllersCodes) {
  Arm arm(kPositionYaml);
  arm.load();
  const auto code = [&](const JointTrajectory& trajectory) {
    return arm.send(goalOf(trajectory)).result.error_code;
  };
  EXPECT_EQ(code(kThreeWaypoints), Action::Result::kInvalidGoal);  // not running yet
  arm.start();
  JointTrajectory elbow = waypoints({{0.1, 0.1}}, {1});
  elbow.joint_names[1] = "elbow";
  EXPECT_EQ(code(elbow), Action::Result::kInvalidJoints);
  JointTrajectory one = waypoints({{0.1}}, {1});
  one.joint_names = {"shoulder"};
  EXPECT_EQ(code(one), Action::Result::kInvalidJoints);  // allow_partial_joints_goal is false
  EXPECT_EQ(code(waypoints({{0.1, 0.1}, {0.2, 0.2}}, {1, 0.5})), Action::Result::kInvalidGoal);
  const auto decision = arm.send(goalOf(waypoints({{0.1, 0.1}}, {1}, {{0.0}})));
  EXPECT_FALSE(decision.accepted);
  EXPECT_THAT(decision.result.error_string, HasSubstr("1 velocities for 2 joints"));
  EXPECT_EQ(arm.controller().activeGoal(), 0u);
}

TEST(JointTrajectoryController, AnEmptyGoalStopsTheArmAndSucceeds) {
  Arm arm(kPositionYaml);
  arm.start();
  ASSERT_TRUE(arm.send(goalOf(waypoints({{1.2, 0.0}}, {2.0}))).accepted);
  arm.stepFor(1.0);
  JointTrajectory empty;
  empty.joint_names = {"shoulder", "wrist"};
  ASSERT_TRUE(arm.send(goalOf(empty)).accepted);
  const auto end = arm.runUntilEnd(arm.lastGoal(), 0.2);
  ASSERT_TRUE(end);
  EXPECT_EQ(*end->end, GoalEnd::kSucceeded);
  EXPECT_NEAR(arm.position("shoulder"), 0.6, 0.02);
}

TEST(JointTrajectoryController, StoppingItPreemptsItsGoal) {
  Arm arm(kPositionYaml);
  arm.start();
  ASSERT_TRUE(arm.send(goalOf(kThreeWaypoints)).accepted);
  arm.stepFor(0.5);
  SwitchControllerRequest stop;
  stop.stop = {"arm_controller"};
  ASSERT_EQ(arm.manager().switchControllers(stop, arm.time(), nullptr), "");
  const auto reports = arm.action().reports->take();
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(*reports.back().end, GoalEnd::kCanceled);
  EXPECT_THAT(arm.command(kThreeWaypoints), HasSubstr("not running"));
}

TEST(JointTrajectoryController, SaysWhatIsWrongWithItsParameters) {
  const auto loadError = [](const std::string& yaml,
                            const std::string& interface = "PositionJointInterface") {
    Arm arm(yaml, interface);
    return arm.manager().load("arm_controller", nullptr);
  };
  EXPECT_THAT(loadError("arm_controller: {type: position_controllers/JointTrajectoryController}"),
              HasSubstr("joints is not set"));
  EXPECT_THAT(
      loadError("arm_controller: {type: velocity_controllers/JointTrajectoryController, joints: [shoulder]}",
                "VelocityJointInterface"),
      HasSubstr("gains/shoulder/p is not set"));
  EXPECT_THAT(
      loadError("arm_controller: {type: velocity_controllers/JointTrajectoryController, joints: [shoulder]}"),
      HasSubstr("needs hardware_interface::VelocityJointInterface"));
  EXPECT_THAT(loadError(kPositionYaml + "  action_monitor_rate: 0\n"),
              HasSubstr("action_monitor_rate must be > 0"));
  Arm arm(kPositionYaml + "  gains: {shoulder: {p: 1}}\n  state_publish_rat: 10\n");
  std::vector<std::string> warnings;
  ASSERT_EQ(arm.manager().load("arm_controller", &warnings), "");
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_THAT(warnings[0],
              HasSubstr("parameter [gains] is not one position_controllers/JointTrajectoryController"));
  EXPECT_THAT(warnings[1], HasSubstr("did you mean [state_publish_rate]?"));
}

}  // namespace
}  // namespace bullet_sim
