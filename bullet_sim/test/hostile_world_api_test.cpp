// Hostile requests at run time, in-process: one row per request to the world API (gazebo_msgs' services as
// WorldApi serves them), the controllers' command inputs, follow_joint_trajectory goals, the controller
// manager's services and spawn poses, each with the refusal it must get. After every row the world must still
// step, the diff-drive robot must still drive, and no pose, twist, joint or published state may be
// non-finite. Three robots: a diff-drive two-wheeler, the ros_control rover and a ros_control arm.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

#include "bullet_sim/common/request_values.h"
#include "bullet_sim/simulation/world_api.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
using Action = FollowJointTrajectoryAction;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// The arm's controllers, under its namespace (/arm): a trajectory controller, and two that take commands.
const char* const kArmYaml = R"(
arm:
  arm_controller:
    type: position_controllers/JointTrajectoryController
    joints: [shoulder, wrist]
  group_controller:
    type: position_controllers/JointGroupPositionController
    joints: [shoulder, wrist]
  shoulder_controller:
    type: position_controllers/JointPositionController
    joint: shoulder
)";

/// Where the diff-drive robot spawns.
constexpr double kDiffX = 0, kDiffY = 0;

/// The three robots in empty.world: "diff" (two_wheeler.urdf's diff drive), "rover" (its controllers running)
/// and "arm" with `arm_controller` running and the others loaded.
class Scene {
 public:
  explicit Scene(const std::string& arm_controller = "group_controller")
      : parameters_(ParameterTree::fromYaml(
            test::readFile(test::packageFile("rover_description", "config/control.yaml")) + kArmYaml,
            "control.yaml")),
        simulation_(test::shippedWorld("empty.world"), options()),
        world_(simulation_) {
    simulation_.spawn("diff", test::parseQuietly(test::twoWheelerWithDiffDrive(), "two_wheeler.urdf"),
                      {.x = kDiffX, .y = kDiffY});
    simulation_.spawn(
        "rover", test::parseQuietly(test::expandXacro("rover_description", "urdf/rover.urdf.xacro"), "rover"),
        {.x = 0, .y = 4});
    simulation_.spawn("arm",
                      test::parseQuietly(test::readFile(test::fixture("robots/trajectory_arm.urdf")), "arm"),
                      {.x = 0, .y = -4});
    test::startControllers(manager("rover"), {"rover_joint_publisher", "rover_velocity_controller"}, 0);
    for (const char* name : {"arm_controller", "group_controller", "shoulder_controller"})
      EXPECT_EQ(manager("arm").load(name, nullptr), "") << name;
    SwitchControllerRequest start;
    start.start = {arm_controller};
    EXPECT_EQ(manager("arm").switchControllers(start, simulation_.time(), nullptr), "");
    for (int i = 0; i < 100; ++i) simulation_.step();
    home_.pose = world_.modelState("diff").pose;
  }

  Simulation& simulation() { return simulation_; }
  WorldApi& world() { return world_; }
  ControllerManager& manager(const std::string& robot) {
    return test::pluginsOf<RosControl>(*simulation_.robot(robot)).at(0)->controllerManager();
  }

  /// `input` on the robot's input whose topic ends with `topic`, as a subscription hands it over; what it
  /// said.
  template <class Input>
  std::string send(const std::string& robot, const std::string& topic, const Input& input) {
    for (const RobotInput<Input>& port : simulation_.robot(robot)->inputs<Input>()) {
      if (port.topic.size() >= topic.size() &&
          port.topic.compare(port.topic.size() - topic.size(), topic.size(), topic) == 0)
        return (*port.handler)(input, simulation_.time());
    }
    ADD_FAILURE() << "robot [" << robot << "] has no input on [" << topic << "]";
    return "";
  }

  /// A follow_joint_trajectory goal to the arm's trajectory controller: its error string, "" when accepted.
  std::string sendGoal(const Action::Goal& goal) {
    const Controller* controller = manager("arm").find("arm_controller");
    const auto& handlers = std::get<ActionHandlers<Action>>(controller->ports().actions.at(0).sink);
    const GoalDecision<Action> decision = handlers.goal(++goals_, goal, simulation_.time());
    return decision.accepted ? "" : decision.result.error_string;
  }

  /// The world steps, the diff-drive robot drives 0.25 s ahead when told, and everything is finite.
  void expectAlive() {
    EXPECT_EQ(world_.setModelState("diff", home_), "");
    const double start = simulation_.time();
    Twist ahead;
    ahead.linear.x() = 0.5;
    for (int k = 0; k < 250; ++k) {
      if (k % 50 == 0) {
        EXPECT_EQ(send("diff", "cmd_vel", ahead), "");
      }
      simulation_.step();
    }
    EXPECT_EQ(send("diff", "cmd_vel", Twist{}), "");
    EXPECT_NEAR(simulation_.time(), start + 0.25, 1e-9) << "the world did not step at its step";
    const double travelled = world_.modelState("diff").pose.translation().x() - home_.pose.translation().x();
    EXPECT_GT(travelled, 0.04) << "the diff-drive robot did not drive";
    EXPECT_DOUBLE_EQ(simulation_.stepSize(), 0.001) << "a refused request changed the step";
    EXPECT_TRUE(simulation_.physics().gravity().isApprox(Eigen::Vector3d(0, 0, -9.81)));
    expectFinite();
  }

 private:
  SimulationOptions options() {
    SimulationOptions options;
    options.parameters = &parameters_;
    return options;
  }
  void expectFinite() const;

  TreeParameters parameters_;
  Simulation simulation_;
  WorldApi world_;
  EntityState home_;  ///< the diff-drive robot at rest where it settled: put back there before each drive
  GoalId goals_ = 0;
};

bool finite(const EntityState& state) {
  return state.pose.matrix().allFinite() && state.linear.allFinite() && state.angular.allFinite();
}

bool finite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double value) { return std::isfinite(value); });
}

void Scene::expectFinite() const {
  for (const NamedState& model : world_.modelStates()) EXPECT_TRUE(finite(model.state)) << model.name;
  for (const NamedState& link : world_.linkStates()) EXPECT_TRUE(finite(link.state)) << link.name;
  for (const std::string& name : simulation_.robotNames()) {
    const Robot& robot = *simulation_.robot(name);
    for (const JointSpec& joint : robot.body().spec().joints) {
      const int index = robot.body().jointIndex(joint.name);
      if (index < 0) continue;
      EXPECT_TRUE(std::isfinite(robot.body().jointPosition(index))) << name << "::" << joint.name;
      EXPECT_TRUE(std::isfinite(robot.body().jointVelocity(index))) << name << "::" << joint.name;
    }
    for (const auto& output : robot.outputs<JointStateSample>()) {
      const JointStateSample& sample = output.stream->latest();
      EXPECT_TRUE(finite(sample.positions) && finite(sample.velocities) && finite(sample.efforts))
          << output.topic;
    }
    for (const auto& output : robot.outputs<Odometry>()) {
      const Odometry& odometry = output.stream->latest();
      EXPECT_TRUE(odometry.pose.matrix().allFinite() && odometry.linear_velocity.allFinite() &&
                  odometry.angular_velocity.allFinite())
          << output.topic;
    }
  }
}

/// One hostile request: what it asks (for the failure message), how it is sent (it returns or throws the
/// refusal), and a piece of the refusal it must get.
struct Row {
  std::string request;
  std::function<std::string(Scene&)> send;
  std::string refusal;
};

/// Sends each row's request to one scene with `arm_controller` running, checking its refusal and that all is
/// well afterwards.
void runRows(const std::vector<Row>& rows, const std::string& arm_controller = "group_controller") {
  Scene scene(arm_controller);
  for (const Row& row : rows) {
    SCOPED_TRACE(row.request);
    std::string refusal;
    try {
      refusal = row.send(scene);
    } catch (const std::exception& e) {
      refusal = e.what();
    }
    EXPECT_THAT(refusal, HasSubstr(row.refusal));
    scene.expectAlive();
  }
}

/// A state at (x, y, z) turned by the quaternion (qx, qy, qz, qw), read as the ROS layer reads a message's.
EntityState stateFrom(double x, double y, double z, double qx, double qy, double qz, double qw) {
  EntityState state;
  state.pose = Eigen::Translation3d(x, y, z) * requireRotation(qx, qy, qz, qw, "pose.orientation");
  return state;
}

EntityState at(double x, double y, double z) { return stateFrom(x, y, z, 0, 0, 0, 1); }

EntityState moving(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
  EntityState state = at(0, 0, 0.1);
  state.linear = linear;
  state.angular = angular;
  return state;
}

std::vector<Row> setModelStateRows() {
  const auto set = [](EntityState state, std::string model = "diff", std::string reference = "") {
    return [=](Scene& scene) { return scene.world().setModelState(model, state, reference); };
  };
  const auto turned = [](double qx, double qy, double qz, double qw) {
    return [=](Scene& scene) {
      return scene.world().setModelState("diff", stateFrom(0, 0, 0.1, qx, qy, qz, qw));
    };
  };
  EntityState tilted = at(0, 0, 0.1);
  tilted.pose.linear()(0, 1) = kNaN;
  return {
      {"position.x NaN", set(at(kNaN, 0, 0)), "model [diff]: pose.position.x [nan] is not a finite number"},
      {"position.y inf", set(at(0, kInf, 0)), "pose.position.y [inf] is not a finite number"},
      {"position.z -inf", set(at(0, 0, -kInf)), "pose.position.z [-inf] is not a finite number"},
      {"position.x 1e300", set(at(1e300, 0, 0)), "pose.position.x [1e+300] m is beyond the limit of 10000 m"},
      {"position.y 2e4", set(at(0, 2e4, 0)), "pose.position.y [20000] m is beyond the limit"},
      {"twist.linear.y NaN", set(moving({0, kNaN, 0}, {0, 0, 0})), "twist.linear.y [nan] is not finite"},
      {"twist.linear.z inf", set(moving({0, 0, kInf}, {0, 0, 0})), "twist.linear.z [inf] is not finite"},
      {"twist.linear.x 1e7", set(moving({1e7, 0, 0}, {0, 0, 0})), "twist.linear.x [1e+07 m/s] is beyond"},
      {"twist.angular.z NaN", set(moving({0, 0, 0}, {0, 0, kNaN})), "twist.angular.z [nan] is not finite"},
      {"twist.angular.y -1e9", set(moving({0, 0, 0}, {0, -1e9, 0})),
       "twist.angular.y [-1e+09 rad/s] is beyond"},
      {"orientation NaN", turned(kNaN, 0, 0, 1), "pose.orientation (x y z w) [nan 0 0 1] is not finite"},
      {"orientation w inf", turned(0, 0, 0, kInf), "pose.orientation (x y z w) [0 0 0 inf] is not finite"},
      {"orientation 1e200", turned(1e200, 1e200, 1e200, 1e200), "is no rotation: its norm [2e+200]"},
      {"orientation 1e-200", turned(1e-200, 1e-200, 1e-200, 1e-200), "is no rotation: its norm [2e-200]"},
      {"orientation 1e-7", turned(0, 0, 1e-7, 0), "is no rotation: its norm [1e-07]"},
      {"orientation 1e7", turned(0, 0, 0, 1e7), "is no rotation: its norm [1e+07]"},
      {"rotation matrix NaN", set(tilted), "model [diff]: pose.orientation is not finite"},
      {"unknown model", set(at(0, 0, 1), "ghost"), "no model [ghost]"},
      {"unknown reference", set(at(0, 0, 1), "diff", "nowhere"), "reference frame [nowhere] names no model"},
      {"far through a reference", set(at(0, 9999, 0), "diff", "rover"), "in the world: pose.position.y"},
  };
}

std::vector<Row> setLinkStateRows() {
  const auto set = [](EntityState state, std::string link = "diff::base_footprint") {
    return [=](Scene& scene) { return scene.world().setLinkState(link, state); };
  };
  return {
      {"link position.x NaN", set(at(kNaN, 0, 0)), "link [diff::base_footprint]: pose.position.x [nan]"},
      {"link position.z 1e300", set(at(0, 0, 1e300)), "pose.position.z [1e+300] m is beyond the limit"},
      {"link twist.angular.y NaN", set(moving({0, 0, 0}, {0, kNaN, 0})),
       "twist.angular.y [nan] is not finite"},
      {"link twist.linear.z -inf", set(moving({0, 0, -kInf}, {0, 0, 0})),
       "twist.linear.z [-inf] is not finite"},
      {"link orientation 1e200",
       [](Scene& scene) {
         return scene.world().setLinkState("diff::base_footprint", stateFrom(0, 0, 1, 0, 1e200, 0, 1e200));
       },
       "is no rotation"},
      {"link of a joint", set(at(0, 0, 1), "arm::upper_arm"), "moves on joint [shoulder]"},
      {"a model as a link", set(at(0, 0, 1), "diff"), "is a model, not a link"},
      {"unknown link", set(at(0, 0, 1), "diff::ghost"), "[diff::ghost] names no model or link"},
  };
}

std::vector<Row> applyBodyWrenchRows() {
  const auto wrench = [](Eigen::Vector3d force, Eigen::Vector3d torque, Eigen::Vector3d point = {0, 0, 0},
                         Schedule schedule = {0, 0.1}, std::string body = "diff::base_footprint") {
    return [=](Scene& scene) {
      return scene.world().applyBodyWrench({body, "", point, force, torque, schedule});
    };
  };
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  return {
      {"force.x NaN", wrench({kNaN, 0, 0}, zero), "wrench.force.x [nan] is not finite"},
      {"force.y NaN after a finite x", wrench({1, kNaN, 0}, zero), "wrench.force.y [nan] is not finite"},
      {"force.z inf", wrench({0, 0, kInf}, zero), "wrench.force.z [inf] is not finite"},
      {"force.x 1e13", wrench({1e13, 0, 0}, zero), "wrench.force.x [1e+13 N] is beyond the 1e+12 N"},
      {"torque.y NaN after a finite x", wrench(zero, {1, kNaN, 0}), "wrench.torque.y [nan] is not finite"},
      {"torque.z -inf", wrench(zero, {0, 0, -kInf}), "wrench.torque.z [-inf] is not finite"},
      {"torque.x -1e13", wrench(zero, {-1e13, 0, 0}), "wrench.torque.x [-1e+13 N m] is beyond"},
      {"reference_point.z NaN", wrench(zero, zero, {0, 0, kNaN}), "reference_point.z [nan] is not a finite"},
      {"reference_point.x 1e5", wrench(zero, zero, {1e5, 0, 0}), "reference_point.x [100000] m is beyond"},
      {"start_time NaN", wrench({1, 0, 0}, zero, zero, {kNaN, 1}), "start_time [nan] is not finite"},
      {"start_time inf", wrench({1, 0, 0}, zero, zero, {kInf, 1}), "start_time [inf] is not finite"},
      {"duration NaN", wrench({1, 0, 0}, zero, zero, {0, kNaN}), "duration [nan] is not a number"},
      {"unknown body", wrench({1, 0, 0}, zero, zero, {0, 1}, "ghost"), "body [ghost] names no model or link"},
      {"the ground", wrench({1, 0, 0}, zero, zero, {0, 1}, "ground_plane::link"), "it takes no wrench"},
      {"unknown reference frame",
       [](Scene& scene) {
         return scene.world().applyBodyWrench({"diff", "nowhere", {}, {1, 0, 0}, {}, {0, 1}});
       },
       "reference frame [nowhere] names no model or link"},
  };
}

std::vector<Row> jointRows() {
  const auto effort = [](double value, Schedule schedule = {0, 0.1}, std::string joint = "arm::wrist") {
    return [=](Scene& scene) { return scene.world().applyJointEffort({joint, value, schedule}); };
  };
  const auto drive = [](double velocity, double max_effort, std::string joint = "arm::wrist") {
    return [=](Scene& scene) {
      scene.world().driveJoint(joint, velocity, max_effort);
      return std::string();
    };
  };
  const auto configure = [](std::map<std::string, double> positions, std::string model = "arm") {
    return [=](Scene& scene) { return scene.world().setModelConfiguration(model, positions); };
  };
  return {
      {"effort NaN", effort(kNaN), "effort on joint [arm::wrist]: effort [nan] is not finite"},
      {"effort -inf", effort(-kInf), "effort [-inf] is not finite"},
      {"effort 1e13", effort(1e13), "effort [1e+13 N m or N] is beyond"},
      {"effort start_time NaN", effort(1, {kNaN, 1}), "start_time [nan] is not finite"},
      {"effort duration NaN", effort(1, {0, kNaN}), "duration [nan] is not a number"},
      {"effort on an unknown joint", effort(1, {0, 1}, "arm::elbow"), "no moving joint [arm::elbow]"},
      {"vel NaN", drive(kNaN, 1), "joint [arm::wrist]: vel [nan] is not finite"},
      {"vel 1e7", drive(1e7, 1), "vel [1e+07 rad/s or m/s] is beyond"},
      {"fmax NaN", drive(1, kNaN), "fmax [nan] is not finite"},
      {"fmax -1", drive(1, -1), "fmax [-1] must be >= 0"},
      {"fmax 1e13", drive(1, 1e13), "fmax [1e+13 N m or N] is beyond"},
      {"vel on an unknown joint", drive(1, 1, "ghost"), "no moving joint [ghost]"},
      {"configuration NaN", configure({{"shoulder", kNaN}}),
       "the position of [shoulder] [nan] is not a finite"},
      {"configuration inf", configure({{"wrist", kInf}}), "the position of [wrist] [inf] is not a finite"},
      {"configuration 1e5", configure({{"wrist", 1e5}}), "[100000] is beyond the limit of 10000"},
      {"configuration of an unknown joint", configure({{"elbow", 0}}),
       "skipped, as Gazebo skips them: [elbow]"},
      {"configuration of the ground", configure({{"x", 0}}, "ground_plane"), "is the world's"},
      {"configuration of an unknown model", configure({{"x", 0}}, "ghost"), "no model [ghost]"},
  };
}

std::vector<Row> physicsRows() {
  const auto physics = [](double step, double rate, Eigen::Vector3d gravity = {0, 0, -9.81}) {
    return [=](Scene& scene) {
      scene.world().setPhysicsProperties({step, rate, gravity});
      return std::string();
    };
  };
  return {
      {"time_step NaN", physics(kNaN, 1000), "time_step [nan] is not finite"},
      {"time_step inf", physics(kInf, 1000), "time_step [inf] is not finite"},
      {"time_step 0", physics(0, 1000), "time_step [0] must be positive"},
      {"time_step -0.001", physics(-0.001, 1000), "time_step [-0.001] must be positive"},
      {"time_step 1e-10", physics(1e-10, 1000), "time_step [1e-10 s] is below the 1e-06 s"},
      {"time_step 10", physics(10, 1000), "time_step [10 s] is beyond the 1 s"},
      {"max_update_rate NaN", physics(0.001, kNaN), "max_update_rate [nan] is not finite"},
      {"max_update_rate inf", physics(0.001, kInf), "max_update_rate [inf] is not finite"},
      {"max_update_rate -1", physics(0.001, -1), "max_update_rate [-1] must be 0 (as fast as possible)"},
      {"max_update_rate 1e-10", physics(0.001, 1e-10),
       "max_update_rate [1e-10] must be 0 (as fast as possible)"},
      {"gravity.x NaN", physics(0.001, 1000, {kNaN, 0, -9.81}), "gravity.x [nan] is not finite"},
      {"gravity.y NaN after a finite x", physics(0.001, 1000, {0, kNaN, -9.81}),
       "gravity.y [nan] is not finite"},
      {"gravity.z -inf", physics(0.001, 1000, {0, 0, -kInf}), "gravity.z [-inf] is not finite"},
      {"gravity.z -1e7", physics(0.001, 1000, {0, 0, -1e7}), "gravity.z [-1e+07 m/s^2] is beyond"},
  };
}

std::vector<Row> queryRows() {
  const auto query = [](std::function<void(WorldApi&)> ask) {  // its answer is not looked at
    return [=](Scene& scene) {
      ask(scene.world());
      return std::string();
    };
  };
  return {
      {"get_model_state of no model", query([](WorldApi& w) { w.modelState("ghost"); }), "no model [ghost]"},
      {"get_model_state in no frame", query([](WorldApi& w) { w.modelState("diff", "nowhere"); }),
       "reference frame [nowhere] names no model or link"},
      {"get_link_state of a model", query([](WorldApi& w) { w.linkState("diff"); }),
       "is a model, not a link"},
      {"get_link_properties of no link", query([](WorldApi& w) { w.linkProperties("diff::ghost"); }),
       "names no model or link"},
      {"get_link_properties of the ground",
       query([](WorldApi& w) { w.linkProperties("ground_plane::link"); }), "without mass"},
      {"get_joint_properties of no joint", query([](WorldApi& w) { w.jointProperties("ghost"); }),
       "no moving joint [ghost]"},
      {"get_model_properties of no model", query([](WorldApi& w) { w.modelProperties("ghost"); }),
       "no model [ghost]"},
  };
}

/// A trajectory for the arm's two joints: one waypoint at `positions` after 1 s, and `edit` applied to it.
JointTrajectory trajectory(const std::function<void(JointTrajectory&)>& edit = {}) {
  JointTrajectory trajectory;
  trajectory.joint_names = {"shoulder", "wrist"};
  trajectory.points.resize(1);
  trajectory.points[0].positions = {0.5, 0.5};
  trajectory.points[0].time_from_start = 1;
  if (edit) edit(trajectory);
  return trajectory;
}

std::vector<Row> trajectoryRows() {
  const auto command = [](JointTrajectory sent) {
    return [=](Scene& scene) { return scene.send("arm", "arm_controller/command", sent); };
  };
  const auto goal = [](const std::function<void(Action::Goal&)>& edit) {
    return [=](Scene& scene) {
      Action::Goal sent;
      sent.trajectory = trajectory();
      edit(sent);
      return scene.sendGoal(sent);
    };
  };
  const auto point = [](const std::function<void(TrajectoryPoint&)>& edit) {
    return trajectory([=](JointTrajectory& t) { edit(t.points[0]); });
  };
  return {
      {"command positions NaN", command(point([](auto& p) { p.positions[1] = kNaN; })),
       "a message whose points[0].positions[1] [nan] is not finite"},
      {"command positions 1e308", command(point([](auto& p) { p.positions = {1e308, -1e308}; })),
       "points[0].positions[0] [1e+308] is beyond the 1e+06"},
      {"command velocities inf", command(point([](auto& p) { p.velocities = {0, kInf}; })),
       "points[0].velocities[1] [inf] is not finite"},
      {"command accelerations NaN", command(point([](auto& p) { p.accelerations = {kNaN, 0}; })),
       "points[0].accelerations[0] [nan] is not finite"},
      {"command effort NaN", command(point([](auto& p) { p.effort = {0, kNaN}; })),
       "points[0].effort[1] [nan] is not finite"},
      {"command time_from_start NaN", command(point([](auto& p) { p.time_from_start = kNaN; })),
       "points[0].time_from_start [nan] is not finite"},
      {"command stamp NaN", command(trajectory([](auto& t) { t.stamp = kNaN; })),
       "header.stamp [nan] is not finite"},
      {"goal positions NaN", goal([](auto& g) { g.trajectory.points[0].positions[0] = kNaN; }),
       "a goal whose points[0].positions[0] [nan] is not finite"},
      {"goal positions -1e308", goal([](auto& g) { g.trajectory.points[0].positions[1] = -1e308; }),
       "points[0].positions[1] [-1e+308] is beyond"},
      {"goal velocities NaN", goal([](auto& g) { g.trajectory.points[0].velocities = {kNaN, kNaN}; }),
       "points[0].velocities[0] [nan] is not finite"},
      {"goal path_tolerance NaN", goal([](auto& g) { g.path_tolerance = {{"shoulder", kNaN, 0, 0}}; }),
       "path_tolerance[0].position [nan] is not finite"},
      {"goal goal_tolerance inf", goal([](auto& g) { g.goal_tolerance = {{"wrist", 0, kInf, 0}}; }),
       "goal_tolerance[0].velocity [inf] is not finite"},
      {"goal goal_time_tolerance NaN", goal([](auto& g) { g.goal_time_tolerance = kNaN; }),
       "goal_time_tolerance [nan] is not finite"},
      {"goal of an unknown joint", goal([](auto& g) { g.trajectory.joint_names[1] = "elbow"; }), "elbow"},
  };
}

std::vector<Row> commandRows() {
  const auto group = [](std::vector<double> data) {
    return [=](Scene& scene) {
      return scene.send("arm", "group_controller/command", Float64ArrayCommand{data});
    };
  };
  const auto single = [](double data) {
    return [=](Scene& scene) {
      return scene.send("arm", "shoulder_controller/command", Float64Command{data});
    };
  };
  const auto twist = [](std::string robot, std::string topic, Eigen::Vector3d linear,
                        Eigen::Vector3d angular) {
    return [=](Scene& scene) { return scene.send(robot, topic, Twist{linear, angular}); };
  };
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  return {
      {"group command [NaN, 0]", group({kNaN, 0}), "a message whose data[0] [nan] is not finite"},
      {"group command [0, NaN]", group({0, kNaN}), "data[1] [nan] is not finite"},
      {"group command [1e308, -1e308]", group({1e308, -1e308}), "data[0] [1e+308] is beyond the 1e+06"},
      {"group command [inf, -inf]", group({kInf, -kInf}), "data[0] [inf] is not finite"},
      {"group command of one value", group({0}), "a command of 1 values for controller [group_controller]"},
      {"single command NaN", single(kNaN), "a message whose data [nan] is not finite"},
      {"single command -1e308", single(-1e308), "data [-1e+308] is beyond"},
      {"diff cmd_vel linear.x NaN", twist("diff", "cmd_vel", {kNaN, 0, 0}, zero),
       "linear.x [nan] is not finite"},
      {"diff cmd_vel linear.y NaN", twist("diff", "cmd_vel", {0, kNaN, 0}, zero),
       "linear.y [nan] is not finite"},
      {"diff cmd_vel angular.z inf", twist("diff", "cmd_vel", zero, {0, 0, kInf}),
       "angular.z [inf] is not finite"},
      {"diff cmd_vel linear.x 1e300", twist("diff", "cmd_vel", {1e300, 0, 0}, zero), "linear.x [1e+300 m/s]"},
      {"rover cmd_vel linear.x NaN", twist("rover", "rover_velocity_controller/cmd_vel", {kNaN, 0, 0}, zero),
       "linear.x [nan] is not finite"},
      {"rover cmd_vel angular.z -1e300",
       twist("rover", "rover_velocity_controller/cmd_vel", zero, {0, 0, -1e300}),
       "angular.z [-1e+300 rad/s] is beyond"},
  };
}

std::vector<Row> controllerManagerRows() {
  const auto load = [](std::string name) {
    return [=](Scene& scene) { return scene.manager("arm").load(name, nullptr); };
  };
  const auto switching = [](std::vector<std::string> start, std::vector<std::string> stop,
                            int strictness = 2) {
    return [=](Scene& scene) {
      SwitchControllerRequest request;
      request.start = start;
      request.stop = stop;
      request.strictness = strictness;
      return scene.manager("arm").switchControllers(request, scene.simulation().time(), nullptr);
    };
  };
  return {
      {"load a controller without parameters", load("ghost_controller"), "its type is not set"},
      {"load a name that is no ROS name", load("bad name"), "its name must be a ROS name"},
      {"load an empty name", load(""), "its name must be a ROS name"},
      {"load twice", load("arm_controller"), "a controller of that name is loaded already"},
      {"unload a running controller", [](Scene& s) { return s.manager("arm").unload("group_controller"); },
       "it is still running: stop it first"},
      {"unload what is not loaded", [](Scene& s) { return s.manager("arm").unload("ghost"); },
       "no controller of that name is loaded"},
      {"start what is not loaded", switching({"ghost"}, {}), "could not start controller [ghost]"},
      {"start and stop one controller", switching({"group_controller"}, {"group_controller"}, 1),
       "asked both to start and to stop"},
      {"start two on the same joints", switching({"arm_controller"}, {}), "would be claimed by"},
      {"stop what is not running", switching({}, {"arm_controller"}), "is not running, so it cannot stop"},
      {"reload libraries with controllers loaded",
       [](Scene& s) { return s.manager("arm").reloadLibraries(false, s.simulation().time()); },
       "controllers are still loaded"},
  };
}

std::vector<Row> spawnRows() {
  const auto spawn = [](Eigen::Vector3d position, Eigen::Quaterniond orientation) {
    return [=](Scene& scene) {
      Diagnostics problems("spawn");
      const SpawnPose pose = spawnPoseFrom(position, orientation, false, problems);
      problems.throwIfErrors();
      scene.simulation().spawn(
          "box", test::parseQuietly(test::readFile(test::fixture("robots/minimal.urdf")), "box"), pose);
      return std::string();
    };
  };
  const Eigen::Quaterniond upright = Eigen::Quaterniond::Identity();
  return {
      {"spawn at x NaN", spawn({kNaN, 0, 1}, upright), "spawn position [nan"},
      {"spawn at z 1e300", spawn({0, 0, 1e300}, upright), "spawn pose z [1e+300] m is beyond the limit"},
      {"spawn turned by NaN", spawn({0, 5, 1}, Eigen::Quaterniond(1, kNaN, 0, 0)),
       "spawn orientation (x y z w)"},
      {"spawn turned by 1e200", spawn({0, 5, 1}, Eigen::Quaterniond(1e200, 0, 0, 1e200)), "is no rotation"},
      {"spawn turned by 1e-200", spawn({0, 5, 1}, Eigen::Quaterniond(1e-200, 0, 0, 0)), "is no rotation"},
      {"spawn a name taken",
       [](Scene& s) {
         s.simulation().spawn(
             "diff", test::parseQuietly(test::readFile(test::fixture("robots/minimal.urdf")), "b"), {.x = 5});
         return "";
       },
       "a robot named [diff] already exists"},
  };
}

TEST(HostileWorldApi, SetModelStateRefusesWhatCannotBeSimulated) { runRows(setModelStateRows()); }

TEST(HostileWorldApi, SetLinkStateRefusesWhatCannotBeSimulated) { runRows(setLinkStateRows()); }

TEST(HostileWorldApi, ApplyBodyWrenchRefusesWhatCannotBeSimulated) { runRows(applyBodyWrenchRows()); }

TEST(HostileWorldApi, JointRequestsRefuseWhatCannotBeSimulated) { runRows(jointRows()); }

TEST(HostileWorldApi, SetPhysicsPropertiesRefusesWhatCannotBeSimulated) { runRows(physicsRows()); }

TEST(HostileWorldApi, QueriesOfWhatIsNotThereAreRefused) { runRows(queryRows()); }

TEST(HostileWorldApi, TrajectoryCommandsAndGoalsThatAreNotFiniteAreRefused) {
  runRows(trajectoryRows(), "arm_controller");
}

TEST(HostileWorldApi, CommandsThatAreNotFiniteAreDroppedBeforeTheirControllers) { runRows(commandRows()); }

TEST(HostileWorldApi, AfterCommandsThatAreNotFiniteTheArmSwitchesBackAndFollowsATrajectory) {
  Scene scene("group_controller");
  for (const std::vector<double>& data :
       std::vector<std::vector<double>>{{kNaN, 0}, {1e308, -1e308}, {0, kInf}}) {
    EXPECT_THAT(scene.send("arm", "group_controller/command", Float64ArrayCommand{data}),
                HasSubstr("a message whose"));
    for (int i = 0; i < 100; ++i) scene.simulation().step();
  }
  SwitchControllerRequest back;
  back.start = {"arm_controller"};
  back.stop = {"group_controller"};
  back.strictness = SwitchControllerRequest::kStrict;
  ASSERT_EQ(scene.manager("arm").switchControllers(back, scene.simulation().time(), nullptr), "");
  Action::Goal goal;
  goal.trajectory = trajectory();  // both joints to 0.5 rad in 1 s
  ASSERT_EQ(scene.sendGoal(goal), "");
  for (int i = 0; i < 1500; ++i) scene.simulation().step();
  for (const char* joint : {"arm::shoulder", "arm::wrist"})
    EXPECT_NEAR(scene.world().jointProperties(joint).position, 0.5, 0.02) << joint;
  scene.expectAlive();
}

TEST(HostileWorldApi, ControllerManagerRefusalsAnswerWithTheReason) { runRows(controllerManagerRows()); }

TEST(HostileWorldApi, SpawnPosesThatAreNotFiniteOrNoRotationAreRefused) { runRows(spawnRows()); }

}  // namespace
}  // namespace bullet_sim
