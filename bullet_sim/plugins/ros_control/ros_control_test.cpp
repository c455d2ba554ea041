// libgazebo_ros_control.so in-process: its tags and transmissions, which wheel model a robot gets, the
// controller manager's services, and the rover (rover_description, Husky's form) driving through its
// diff_drive_controller against the unicycle, in the world.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/ros_control/diff_drive_controller.h"
#include "bullet_sim/common/diagnostics.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

std::string roverUrdf() { return test::expandXacro("rover_description", "urdf/rover.urdf.xacro"); }

std::string controlYaml() {
  return test::readFile(test::packageFile("rover_description", "config/control.yaml"));
}

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); }

/// The rover in empty.world with `yaml` on the parameter server's root, its controllers loaded and started.
class Rover {
 public:
  explicit Rover(const std::string& yaml = controlYaml())
      : parameters_(ParameterTree::fromYaml(yaml, "control.yaml")),
        simulation_(test::shippedWorld("empty.world"), options()) {
    robot_ = &simulation_.spawn("rover", test::parseQuietly(roverUrdf(), "rover"), SpawnPose{});
    plugin_ = test::pluginsOf<RosControl>(*robot_).at(0);
  }

  SimulationOptions options() {
    SimulationOptions options;
    options.parameters = &parameters_;
    return options;
  }
  ControllerManager& manager() { return plugin_->controllerManager(); }
  Simulation& simulation() { return simulation_; }
  Robot& robot() { return *robot_; }

  /// Loads and starts `names` as the spawner does (STRICT).
  void spawnControllers(const std::vector<std::string>& names) {
    test::startControllers(manager(), names, simulation_.time());
  }
  DiffDriveController& driveController() {
    return dynamic_cast<DiffDriveController&>(*manager().find("rover_velocity_controller"));
  }
  /// cmd_vel to the drive controller, as it arrives from a subscription now.
  std::string command(double linear, double angular) {
    Twist twist;
    twist.linear.x() = linear;
    twist.angular.z() = angular;
    for (const auto& port : driveController().ports().inputs) {
      if (port.topic == "rover_velocity_controller/cmd_vel")
        return std::get<InputHandler<Twist>>(port.sink)(twist, simulation_.time());
    }
    return "no cmd_vel";
  }
  /// Steps for `seconds`, sending the command every 0.1 s as `rostopic pub -r 10` does.
  void drive(double linear, double angular, double seconds) {
    const long steps = std::lround(seconds / simulation_.stepSize());
    const long every = std::lround(0.1 / simulation_.stepSize());
    for (long k = 0; k < steps; ++k) {
      if (k % every == 0) {
        EXPECT_EQ(command(linear, angular), "");
      }
      simulation_.step();
    }
  }
  Eigen::Isometry3d groundTruth() const { return robot_->body().linkPose("base_link"); }

 private:
  TreeParameters parameters_;
  Simulation simulation_;
  Robot* robot_ = nullptr;
  RosControl* plugin_ = nullptr;
};

TEST(RosControl, ReadsTheRoversTransmissionsAndTags) {
  const ModelSpec model = test::parseQuietly(roverUrdf(), "rover");
  ASSERT_EQ(model.plugins.size(), 2u);
  const auto* config = model.plugins[0].configAs<RosControlConfig>();
  ASSERT_NE(config, nullptr);
  EXPECT_TRUE(config->namespace_given);
  EXPECT_EQ(config->robot_namespace, "/");
  EXPECT_EQ(config->control_period, 0);
  ASSERT_EQ(config->joints.size(), 4u);
  for (const auto& joint : config->joints)
    EXPECT_EQ(joint.interface, JointInterface::kVelocity) << joint.name;
  EXPECT_EQ(config->joints[0].name, "front_left_wheel");
}

TEST(RosControl, DrivesTheRoverOnTheUnicyclesArc) {
  Rover rover;
  rover.spawnControllers({"rover_joint_publisher", "rover_velocity_controller"});
  EXPECT_EQ(rover.robot().body().spec().name, "rover");
  // v 0.5 m/s and w 0.3 rad/s: after 1 s of spin-up, 5 s along an arc of R = 5/3 m.
  rover.drive(0.5, 0.3, 1.0);
  const Eigen::Isometry3d start = rover.groundTruth();
  const double x0 = start.translation().x(), y0 = start.translation().y(), yaw0 = yawOf(start);
  rover.drive(0.5, 0.3, 5.0);
  const double radius = 0.5 / 0.3, yaw = yaw0 + 0.3 * 5.0;
  const Eigen::Vector2d expected(x0 + radius * (std::sin(yaw) - std::sin(yaw0)),
                                 y0 - radius * (std::cos(yaw) - std::cos(yaw0)));
  const Eigen::Isometry3d end = rover.groundTruth();
  EXPECT_LT((end.translation().head<2>() - expected).norm(), 0.05)
      << "ended at " << end.translation().head<2>().transpose() << ", the unicycle at "
      << expected.transpose();
  EXPECT_NEAR(std::remainder(yawOf(end) - yaw, 2 * M_PI), 0, 0.05);

  // The controller's odometry (from the wheels) agrees with the ground truth: the odom frame is the spawn
  // pose.
  const DiffDriveOdometry& odometry = rover.driveController().odometry();
  EXPECT_NEAR(odometry.x(), end.translation().x(), 0.05);
  EXPECT_NEAR(odometry.y(), end.translation().y(), 0.05);
  EXPECT_NEAR(std::remainder(odometry.heading() - yawOf(end), 2 * M_PI), 0, 0.05);
}


/// What parseModel says of the rover with its ros_control block edited by `edit` (its <plugin> element).
template <class Edit>
Diagnostics parseEdited(Edit edit) {
  const std::string urdf = test::editUrdf(roverUrdf(), [&](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      auto* plugin = gazebo->FirstChildElement("plugin");
      if (plugin && std::string(plugin->Attribute("filename")) == "libgazebo_ros_control.so")
        edit(robot, *plugin);
    }
  });
  Diagnostics diagnostics("rover");
  readModel(urdf, PackageResolver::fromEnvironment(), PluginRegistry::builtin(), diagnostics);
  return diagnostics;
}

std::string all(const std::vector<std::string>& messages) {
  std::string text;
  for (const auto& message : messages) text += message + "\n";
  return text;
}

TEST(RosControl, RefusesWhatDefaultRobotHwSimCannotDo) {
  const Diagnostics diagnostics = parseEdited([](tinyxml2::XMLElement& robot, tinyxml2::XMLElement& plugin) {
    plugin.InsertNewChildElement("robotSimType")->SetText("my_robot/MyRobotHWSim");
    plugin.InsertNewChildElement("legacyModeNS")->SetText("true");
    auto* transmission = robot.FirstChildElement("transmission");
    transmission->FirstChildElement("joint")->SetAttribute("name", "front_left_whel");
    transmission = transmission->NextSiblingElement("transmission");
    transmission->FirstChildElement("joint")->FirstChildElement("hardwareInterface")->SetText(
        "hardware_interface/PosVelJointInterface");
    transmission = transmission->NextSiblingElement("transmission");
    transmission->FirstChildElement("joint")->FirstChildElement("hardwareInterface")->SetText(
        "EffortJointInterface");
  });
  const std::string errors = all(diagnostics.errors());
  EXPECT_THAT(errors,
              HasSubstr("<robotSimType> [my_robot/MyRobotHWSim] is a RobotHWSim bullet_sim does not have: "
                        "only gazebo_ros_control/DefaultRobotHWSim is simulated"));
  EXPECT_THAT(errors, HasSubstr("transmission [front_left_wheel_trans] (line"));
  EXPECT_THAT(errors, HasSubstr("names joint [front_left_whel], which the robot does not have (did you mean "
                                "[front_left_wheel]?)"));
  EXPECT_THAT(errors,
              HasSubstr("joint [front_right_wheel] <hardwareInterface> "
                        "[hardware_interface/PosVelJointInterface] is not one DefaultRobotHWSim drives"));
  EXPECT_EQ(diagnostics.errors().size(), 3u) << errors;
  const std::string warnings = all(diagnostics.warnings());
  EXPECT_THAT(warnings, HasSubstr("<legacyModeNS> is gone from Noetic's gazebo_ros_control: ignored"));
  EXPECT_THAT(warnings, HasSubstr("joint [rear_left_wheel] <hardwareInterface> [EffortJointInterface] is the "
                                  "deprecated spelling of [hardware_interface/EffortJointInterface]"));
  EXPECT_EQ(diagnostics.warnings().size(), 2u) << warnings;
}

/// The wheel model the rover gets with `yaml` as its namespace's parameters and its plugin block edited.
template <class Edit>
std::string roverWheelModel(const std::string& yaml, Edit edit, Diagnostics* diagnostics) {
  const std::string urdf = test::editUrdf(roverUrdf(), edit);
  const ModelSpec model = parseModel(urdf, "rover", PackageResolver::fromEnvironment());
  return rosControlWheelModel(*model.plugins[0].configAs<RosControlConfig>(), model,
                              ParameterTree::fromYaml(yaml, "parameters"), *diagnostics);
}

TEST(RosControl, WheelsDrivenThroughItGetTheDriveWheelModels) {
  Diagnostics diagnostics("rover");
  const auto unchanged = [](tinyxml2::XMLElement&) {};
  // The diff drive's wheels, or without one the continuous joints with velocity or effort transmissions.
  EXPECT_EQ(roverWheelModel(controlYaml(), unchanged, &diagnostics), kDefaultWheelModel);
  EXPECT_EQ(roverWheelModel("{}", unchanged, &diagnostics), kDefaultWheelModel);
  const auto contact = [](tinyxml2::XMLElement& robot) {
    auto* gazebo = robot.FirstChildElement("gazebo");
    gazebo->FirstChildElement("plugin")->InsertNewChildElement("wheelModel")->SetText("contact");
  };
  EXPECT_EQ(roverWheelModel(controlYaml(), contact, &diagnostics), "contact");
  // Position transmissions make no wheels.
  const auto positions = [](tinyxml2::XMLElement& robot) {
    for (auto* t = robot.FirstChildElement("transmission"); t; t = t->NextSiblingElement("transmission"))
      t->FirstChildElement("joint")->FirstChildElement("hardwareInterface")->SetText(
          "hardware_interface/PositionJointInterface");
  };
  EXPECT_EQ(roverWheelModel("{}", positions, &diagnostics), "contact");
  EXPECT_THAT(diagnostics.errors(), IsEmpty());
}

TEST(RosControl, RaycastCannotPushOtherJointsByEffort) {
  // The diff drive names the front wheels only: the rear ones, pushed by a PID loop, are not wheels.
  const std::string yaml =
      "drive: {type: diff_drive_controller/DiffDriveController, left_wheel: front_left_wheel, "
      "right_wheel: front_right_wheel}\n"
      "gazebo_ros_control: {pid_gains: {rear_left_wheel: {p: 10.0}}}\n";
  Diagnostics diagnostics("rover");
  EXPECT_EQ(roverWheelModel(yaml, [](tinyxml2::XMLElement&) {}, &diagnostics), "contact");
  EXPECT_THAT(diagnostics.errors(), IsEmpty());
  const auto raycast = [](tinyxml2::XMLElement& robot) {
    robot.FirstChildElement("gazebo")
        ->FirstChildElement("plugin")
        ->InsertNewChildElement("wheelModel")
        ->SetText("raycast");
  };
  EXPECT_EQ(roverWheelModel(yaml, raycast, &diagnostics), "raycast");
  ASSERT_EQ(diagnostics.errors().size(), 1u);
  EXPECT_THAT(diagnostics.errors()[0], HasSubstr("cannot push joint [rear_left_wheel] by effort"));
}

TEST(RosControl, LivesInTheModelsNamespaceUnlessTold) {
  RosControlConfig config;
  EXPECT_EQ(rosControlNamespace(config, "husky", std::nullopt), "husky");
  config.namespace_given = true;
  config.robot_namespace = "/";
  EXPECT_EQ(rosControlNamespace(config, "husky", std::nullopt), "");
  EXPECT_EQ(rosControlNamespace(config, "husky", std::string("/robot1/")), "robot1");
}

TEST(RosControl, ControllerManagerLoadsSwitchesListsAndUnloads) {
  Rover rover;
  ControllerManager& manager = rover.manager();
  EXPECT_EQ(manager.load("rover_velocity_controller", nullptr), "");
  EXPECT_EQ(manager.load("rover_joint_publisher", nullptr), "");
  EXPECT_THAT(manager.load("rover_joint_publisher", nullptr), HasSubstr("is loaded already"));
  const auto listed = manager.list();
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0].name, "rover_velocity_controller");
  EXPECT_EQ(listed[0].state, "initialized");
  EXPECT_EQ(listed[0].type, "diff_drive_controller/DiffDriveController");
  ASSERT_EQ(listed[0].claimed_resources.size(), 1u);
  EXPECT_EQ(listed[0].claimed_resources[0].hardware_interface, "hardware_interface::VelocityJointInterface");
  EXPECT_THAT(listed[0].claimed_resources[0].resources,
              ElementsAre("front_left_wheel", "rear_left_wheel", "front_right_wheel", "rear_right_wheel"));
  EXPECT_EQ(listed[1].claimed_resources[0].hardware_interface, "hardware_interface::JointStateInterface");
  EXPECT_THAT(listed[1].claimed_resources[0].resources, IsEmpty());

  SwitchControllerRequest request;
  request.strictness = SwitchControllerRequest::kStrict;
  request.start = {"rover_velocity_controller", "no_such_controller"};
  EXPECT_THAT(
      manager.switchControllers(request, 0, nullptr),
      HasSubstr("could not start controller [no_such_controller]: no controller of that name is loaded"));
  EXPECT_EQ(manager.list()[0].state, "initialized");  // STRICT: nothing happened
  request.strictness = SwitchControllerRequest::kBestEffort;
  EXPECT_EQ(manager.switchControllers(request, 0, nullptr), "");
  EXPECT_EQ(manager.list()[0].state, "running");
  request.strictness = SwitchControllerRequest::kStrict;
  request.start = {"rover_velocity_controller"};
  EXPECT_THAT(manager.switchControllers(request, 0, nullptr), HasSubstr("is running already"));
  EXPECT_THAT(manager.unload("rover_velocity_controller"), HasSubstr("it is still running: stop it first"));

  const uint64_t revision = manager.revision();
  request.start = {};
  request.stop = {"rover_velocity_controller"};
  EXPECT_EQ(manager.switchControllers(request, 0, nullptr), "");
  EXPECT_EQ(manager.list()[0].state, "stopped");
  EXPECT_EQ(manager.unload("rover_velocity_controller"), "");
  EXPECT_NE(manager.revision(), revision);
  ASSERT_EQ(manager.portGroups().size(), 1u);
  EXPECT_EQ(manager.portGroups()[0].name, "controller [rover_joint_publisher]");
  EXPECT_THAT(manager.reloadLibraries(false, 0), HasSubstr("1 controllers are still loaded"));
  EXPECT_EQ(manager.reloadLibraries(true, 0), "");
  EXPECT_THAT(manager.list(), IsEmpty());
}

TEST(RosControl, EveryParameterOfTheRoversControlYamlIsRead) {
  Rover rover;
  std::vector<std::string> warnings;
  EXPECT_EQ(rover.manager().load("rover_joint_publisher", &warnings), "");
  EXPECT_EQ(rover.manager().load("rover_velocity_controller", &warnings), "");
  EXPECT_THAT(warnings, IsEmpty());
}

TEST(RosControl, TwoControllersCannotClaimOneJoint) {
  Rover rover(controlYaml() + "second_drive:\n  type: diff_drive_controller/DiffDriveController\n"
                              "  left_wheel: front_left_wheel\n  right_wheel: front_right_wheel\n");
  rover.spawnControllers({"rover_velocity_controller"});
  ASSERT_EQ(rover.manager().load("second_drive", nullptr), "");
  SwitchControllerRequest request;
  request.start = {"second_drive"};
  EXPECT_THAT(
      rover.manager().switchControllers(request, 0, nullptr),
      HasSubstr("joint [front_left_wheel] would be claimed by rover_velocity_controller, second_drive"));
  request.stop = {"rover_velocity_controller"};
  EXPECT_EQ(rover.manager().switchControllers(request, 0, nullptr), "");  // a handover is no conflict
}

TEST(RosControl, LoadControllerSaysWhatIsWrong) {
  Rover rover(controlYaml() +
              "mystery:\n  type: diff_drive_controller/DiffDriveControler\n"
              "broken_drive:\n  type: diff_drive_controller/DiffDriveController\n"
              "  left_wheel: front_left_wheel\n  right_wheel: [front_right_wheel, rear_right_wheel]\n"
              "odd_publisher:\n  type: joint_state_controller/JointStateController\n"
              "  publish_rate: 10\n  publish_rat: 20\n");
  ControllerManager& manager = rover.manager();
  const std::string unknown = manager.load("mystery", nullptr);
  EXPECT_THAT(unknown, HasSubstr("could not load controller [mystery]: type [diff_drive_controller/"
                                 "DiffDriveControler] is not a controller type bullet_sim has (did you mean "
                                 "[diff_drive_controller/DiffDriveController]?); it has "
                                 "joint_state_controller/JointStateController, diff_drive_controller/"
                                 "DiffDriveController, velocity_controllers/JointVelocityController"));
  EXPECT_THAT(manager.load("nothing_here", nullptr),
              HasSubstr("its type is not set: did you load the controller configuration onto the parameter "
                        "server (/nothing_here/type)?"));
  EXPECT_THAT(manager.load("broken_drive", nullptr),
              HasSubstr("left_wheel has 1 wheels and right_wheel 2: give each side as many"));
  EXPECT_THAT(manager.load("bad name", nullptr), HasSubstr("its name must be a ROS name"));
  std::vector<std::string> warnings;
  EXPECT_EQ(manager.load("odd_publisher", &warnings), "");
  EXPECT_THAT(warnings,
              ElementsAre(HasSubstr("parameter [publish_rat] is not one "
                                    "joint_state_controller/JointStateController reads (did you mean "
                                    "[publish_rate]?): ignored")));
  EXPECT_THAT(manager.list(), ::testing::SizeIs(1));
}

TEST(RosControl, JointStatesHaveEveryWheelAtThePublishRate) {
  Rover rover;
  rover.spawnControllers({"rover_joint_publisher"});
  const auto& states = *std::get<const Stream<JointStateSample>*>(
      rover.manager().find("rover_joint_publisher")->ports().outputs.at(0).stream);
  for (int k = 0; k < 1000; ++k) rover.simulation().step();
  // At the first update (ros_controllers starts 1.001 periods back), then every 20 ms:
  // 0.001, 0.02, ..., 1.0 s.
  EXPECT_EQ(states.count(), 51u);
  EXPECT_THAT(states.latest().names,
              ElementsAre("front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"));
  EXPECT_EQ(states.latest().positions.size(), 4u);
}

TEST(RosControl, EStopHoldsTheWheelsAndResetZeroesTheOdometry) {
  const std::string urdf =
      test::withPluginTags(roverUrdf(), "libgazebo_ros_control.so", {{"eStopTopic", "e_stop"}});
  TreeParameters parameters(ParameterTree::fromYaml(controlYaml(), "control.yaml"));
  SimulationOptions options;
  options.parameters = &parameters;
  Simulation simulation(test::shippedWorld("empty.world"), options);
  Robot& robot = simulation.spawn("rover", test::parseQuietly(urdf, "rover"), SpawnPose{});
  RosControl& plugin = *test::pluginsOf<RosControl>(robot).at(0);
  ASSERT_EQ(plugin.ports().inputs.at(0).topic, "e_stop");
  test::startControllers(plugin.controllerManager(), {"rover_velocity_controller"}, 0);
  const auto e_stop = std::get<InputHandler<BoolCommand>>(plugin.ports().inputs.at(0).sink);
  auto& drive =
      dynamic_cast<DiffDriveController&>(*plugin.controllerManager().find("rover_velocity_controller"));
  const auto cmd_vel = std::get<InputHandler<Twist>>(drive.ports().inputs.at(0).sink);
  Twist forward;
  forward.linear.x() = 0.5;
  const int wheel = robot.body().jointIndex("front_left_wheel");
  for (int k = 0; k < 1000; ++k) {
    if (k % 100 == 0) cmd_vel(forward, simulation.time());
    if (k == 500) e_stop({true}, simulation.time());
    simulation.step();
  }
  EXPECT_NEAR(robot.body().jointVelocity(wheel), 0, 1e-3);  // held while the command goes on
  e_stop({false}, simulation.time());
  for (int k = 0; k < 500; ++k) {
    if (k % 100 == 0) cmd_vel(forward, simulation.time());
    simulation.step();
  }
  EXPECT_NEAR(robot.body().jointVelocity(wheel), 0.5 / 0.165, 0.05);
  EXPECT_GT(drive.odometry().x(), 0.2);
  simulation.resetWorld();
  simulation.step();
  EXPECT_NEAR(drive.odometry().x(), 0, 1e-3);
  EXPECT_NEAR(robot.body().linkPose("base_footprint").translation().x(), 0, 1e-3);
}

TEST(JointLimits, ParametersOverrideTheUrdfAsJointLimitsInterfaceReadsThem) {
  JointSpec wheel;
  wheel.type = JointSpec::Type::kContinuous;
  wheel.effort = 60;
  wheel.velocity = 20;
  JointLimits limits;
  ASSERT_TRUE(JointLimits::fromUrdf(wheel, &limits));
  EXPECT_FALSE(limits.has_position_limits);
  EXPECT_TRUE(limits.angle_wraparound);
  EXPECT_DOUBLE_EQ(limits.max_velocity, 20);
  EXPECT_DOUBLE_EQ(limits.effortBound(), 60);
  // A false flag unsets its limit, a true one takes its value, an absent one leaves the URDF's.
  ASSERT_TRUE(JointLimits::fromParameters(
      ParameterTree::fromYaml("{has_velocity_limits: true, max_velocity: 2.0, has_acceleration_limits: true, "
                              "max_acceleration: 10.0, has_effort_limits: false}",
                              "joint_limits"),
      &limits));
  EXPECT_DOUBLE_EQ(limits.max_velocity, 2.0);
  EXPECT_TRUE(limits.has_acceleration_limits);
  EXPECT_FALSE(limits.has_effort_limits);
  EXPECT_FALSE(JointLimits::fromParameters(ParameterTree(), &limits));

  JointSpec bare;
  bare.type = JointSpec::Type::kContinuous;
  EXPECT_FALSE(JointLimits::fromUrdf(bare, &limits));  // no <limit>: nothing to enforce
}

TEST(JointLimits, SaturationClipsEachInterfaceAsRosControlDoes) {
  JointLimits limits;
  limits.has_position_limits = true;
  limits.min_position = -1;
  limits.max_position = 1;
  limits.has_velocity_limits = true;
  limits.max_velocity = 2;
  limits.has_acceleration_limits = true;
  limits.max_acceleration = 10;
  limits.has_effort_limits = true;
  limits.max_effort = 5;
  // Velocity: within +-2, and at most 10 * dt from the last command: 0.1, 0.2, ... up to 2.
  JointSaturation velocity(JointInterface::kVelocity, limits);
  for (int k = 1; k <= 30; ++k) EXPECT_NEAR(velocity.clip(50, 0, 0, 0.01), std::min(2.0, 0.1 * k), 1e-12);
  // Position: within [-1, 1], and at most 2 * dt from the last command, which starts where the joint is.
  JointSaturation position(JointInterface::kPosition, limits);
  EXPECT_NEAR(position.clip(3, 0.5, 0, 0.01), 0.52, 1e-12);
  for (int k = 0; k < 100; ++k) position.clip(3, 0.5, 0, 0.01);
  EXPECT_DOUBLE_EQ(position.clip(3, 0.5, 0, 0.01), 1.0);
  // Effort: within +-5, and none that pushes further past a limit.
  JointSaturation effort(JointInterface::kEffort, limits);
  EXPECT_DOUBLE_EQ(effort.clip(9, 0, 0, 0.01), 5);
  EXPECT_DOUBLE_EQ(effort.clip(9, 1.2, 0, 0.01), 0);
  EXPECT_DOUBLE_EQ(effort.clip(-9, 1.2, 0, 0.01), -5);
  EXPECT_DOUBLE_EQ(effort.clip(-9, 0, -3, 0.01), 0);
}

TEST(RosControl, JointLimitsParametersCapTheWheels) {
  // joint_limits/<joint> in the robot's namespace overrides the URDF's 20 rad/s: a wheel commanded at
  // 1 m/s / 0.165 m = 6.1 rad/s turns at 2 rad/s, the others as commanded.
  Rover rover(controlYaml() +
              "joint_limits: {front_left_wheel: {has_velocity_limits: true, max_velocity: 2.0}}\n");
  rover.spawnControllers({"rover_velocity_controller"});
  rover.drive(1.0, 0.0, 1.0);
  const RobotBody& body = rover.robot().body();
  EXPECT_NEAR(body.jointVelocity(body.jointIndex("front_left_wheel")), 2.0, 1e-6);
  EXPECT_GT(body.jointVelocity(body.jointIndex("rear_left_wheel")), 5.0);
}
}  // namespace
}  // namespace bullet_sim
