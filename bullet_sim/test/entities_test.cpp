// Gazebo's world API in the core (WorldApi over a Simulation), against analytic truth: teleports that the
// lidar sees, reference frames, wrenches and efforts over their windows, joint configurations, properties,
// and physics properties that change the step and gravity. Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/scene/simulation_images.h"
#include "bullet_sim/simulation/world_api.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

/// A world of the ground and one static 1 m crate standing at x = 2 (its near face at x = 1.5).
WorldSpec crateWorld(bool weightless = false) {
  const std::string sdf = R"(<?xml version="1.0"?>
<sdf version="1.6">
  <world name="crates">
    <include><uri>model://ground_plane</uri></include>
    <model name="crate">
      <static>true</static>
      <pose>2 0 0.5 0 0 0</pose>
      <link name="body">
        <collision name="box"><geometry><box><size>1 1 1</size></box></geometry></collision>
        <visual name="box"><geometry><box><size>1 1 1</size></box></geometry></visual>
      </link>
    </model>
  </world>
</sdf>)";
  WorldSpec world = parseWorld(sdf, "crates.world", PackageResolver::fromEnvironment(), nullptr);
  if (weightless) world.gravity = Eigen::Vector3d::Zero();
  return world;
}

ModelSpec fixtureRobot(const std::string& file) {
  return test::parseQuietly(test::readFile(test::fixture("robots/" + file)), file);
}

/// two_wheeler.urdf with a diff drive on `wheel_model` wheels whose motors have `torque` [N m].
ModelSpec twoWheeler(const std::string& wheel_model, const std::string& torque = "5") {
  return test::parseQuietly(
      test::twoWheelerWithDiffDrive({{"wheelTorque", torque}, {"wheelModel", wheel_model}}),
      "two_wheeler.urdf");
}

EntityState at(double x, double y, double z, double yaw) {
  EntityState state;
  state.pose = Eigen::Translation3d(x, y, z) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
  return state;
}

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); }

/// The mast's beam along its +x after its next scan.
double rangeAhead(Simulation& simulation, const Stream<LaserScan>& lidar) {
  const uint64_t scans = lidar.count();
  test::stepUntil(
      simulation, [&] { return lidar.count() > scans; }, 1.0, "a scan");
  return lidar.latest().ranges[90];
}

TEST(Entities, WorldModelsAreModelsBeforeTheRobotsWithTheirLinks) {
  Simulation simulation(crateWorld());
  WorldApi world(simulation);
  simulation.spawn("robot", twoWheeler("contact"), {.x = -1});
  EXPECT_THAT(world.modelNames(), ElementsAre("ground_plane", "crate", "robot"));
  std::vector<std::string> links;
  for (const NamedState& link : world.linkStates()) links.push_back(link.name);
  EXPECT_THAT(links, ElementsAre("ground_plane::link", "crate::body", "robot::base_footprint",
                                 "robot::left_wheel", "robot::right_wheel"));
  const EntityState crate = world.modelState("crate");
  EXPECT_TRUE(crate.pose.translation().isApprox(Eigen::Vector3d(2, 0, 0.5)));
  EXPECT_TRUE(crate.linear.isZero());
  const EntityState robot = world.modelState("robot");
  EXPECT_NEAR(robot.pose.translation().x(), -1, 1e-9);
  EXPECT_NEAR(robot.pose.translation().z(), 0, 1e-3) << "the root link, base_footprint, is on the ground";
}

TEST(Entities, ATeleportedRobotIsWhereTheLidarSeesIt) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(crateWorld(/*weightless=*/true));
    WorldApi world(simulation);
    Robot& mast = simulation.spawn("mast", fixtureRobot("lidar_mast.urdf"), {});
    Robot& robot = simulation.spawn("robot", twoWheeler(wheel_model), {.x = -2});
    const Stream<LaserScan>& lidar = *mast.outputs<LaserScan>().at(0).stream;
    EXPECT_NEAR(rangeAhead(simulation, lidar), 1.5, 1e-4) << "the crate";
    const int left = robot.body().jointIndex("left_wheel_joint");
    world.setModelConfiguration("robot", {{"left_wheel_joint", 0.7}});
    // The box body (0.4 m long, 0.1 m high, 0.05 m above base_footprint) across the beam, 0.5 m up.
    EntityState target = at(1.2, 0, 0.4, M_PI);
    target.linear = Eigen::Vector3d(0, 0.01, 0);
    EXPECT_EQ(world.setModelState("robot", target), "");
    const EntityState now = world.modelState("robot");
    EXPECT_TRUE(now.pose.isApprox(target.pose, 1e-12));
    EXPECT_TRUE(now.linear.isApprox(target.linear, 1e-12));
    EXPECT_NEAR(robot.body().jointPosition(left), 0.7, 1e-9) << "joints keep their positions";
    EXPECT_NEAR(rangeAhead(simulation, lidar), 1.0, 2e-3) << "the robot's body, 0.2 m before its root";
  }
}

TEST(Entities, AStaticWorldModelMovesForTheLidarAndResetWorldPutsItBack) {
  Simulation simulation(crateWorld());
  WorldApi world(simulation);
  Robot& mast = simulation.spawn("mast", fixtureRobot("lidar_mast.urdf"), {});
  const Stream<LaserScan>& lidar = *mast.outputs<LaserScan>().at(0).stream;
  EXPECT_NEAR(rangeAhead(simulation, lidar), 1.5, 1e-4);
  EXPECT_EQ(world.setModelState("crate", at(1.5, 0, 0.5, 0)), "");
  EXPECT_NEAR(rangeAhead(simulation, lidar), 1.0, 1e-4);
  EXPECT_TRUE(simulation.worldModelPose(1).translation().isApprox(Eigen::Vector3d(1.5, 0, 0.5)));
  EntityState spinning = at(1.8, 0, 0.5, 0);
  spinning.angular.z() = 1;
  EXPECT_THAT(world.setModelState("crate", spinning), HasSubstr("twist is ignored"));
  EXPECT_NEAR(rangeAhead(simulation, lidar), 1.3, 1e-4);
  SimulationImages images(simulation, []() -> SceneRenderer& { throw std::logic_error("nothing is drawn"); });
  const SceneMesh& drawn = images.sceneFor({}).meshes.at(1);  // the ground's, then the crate's
  EXPECT_TRUE(drawn.pose.translation().isApprox(Eigen::Vector3d(1.8, 0, 0.5))) << "cameras see it there";
  simulation.resetWorld();
  EXPECT_NEAR(rangeAhead(simulation, lidar), 1.5, 1e-4);
  EXPECT_TRUE(world.modelState("crate").pose.translation().isApprox(Eigen::Vector3d(2, 0, 0.5)));
}

TEST(Entities, AMovedStaticWorldModelCarriesWhatFallsOnIt) {
  // The crate shares a compound with the static primitives of its cell of the floor: moving it moves its
  // child.
  Simulation simulation(crateWorld());
  WorldApi world(simulation);
  EXPECT_EQ(world.setModelState("crate", at(0, 0, 0.5, 0)), "");
  simulation.spawn("box", fixtureRobot("minimal.urdf"), {.z = 2});
  for (int i = 0; i < 2000; ++i) simulation.step();
  EXPECT_NEAR(world.modelState("box").pose.translation().z(), 1.1, 0.01)
      << "on the crate's top (1 m), not on the ground";
  EXPECT_EQ(world.setModelState("crate", at(2, 0, 0.5, 0)), "");
  for (int i = 0; i < 2000; ++i) simulation.step();
  EXPECT_NEAR(world.modelState("box").pose.translation().z(), 0.1, 0.01) << "on the ground, the crate gone";
}

TEST(Entities, StatesAreReadAndSetInTheReferenceFramesGazeboUses) {
  Simulation simulation(crateWorld(/*weightless=*/true));
  WorldApi world(simulation);
  simulation.spawn("a", twoWheeler("contact"), {.x = 1, .y = 2, .yaw = M_PI / 2, .z = 1});
  simulation.spawn("b", twoWheeler("contact"), {.x = 3, .y = 2, .z = 1});
  const EntityState b_from_a = world.modelState("b", "a");
  EXPECT_TRUE(b_from_a.pose.translation().isApprox(Eigen::Vector3d(0, -2, 0), 1e-9));
  EXPECT_NEAR(yawOf(b_from_a.pose), -M_PI / 2, 1e-9);
  // A link as the reference, scoped or bare (base_link is a's, the first model that has one).
  const EntityState b_from_link = world.modelState("b", "a::base_link");
  EXPECT_TRUE(b_from_link.pose.translation().isApprox(Eigen::Vector3d(0, -2, -0.05), 1e-9));
  EXPECT_TRUE(world.modelState("b", "base_link").pose.isApprox(b_from_link.pose, 1e-12));
  EXPECT_TRUE(world.modelState("b", "world").pose.isApprox(world.modelState("b").pose, 1e-12));

  EntityState ahead = at(1, 0, 0, 0);
  ahead.linear = Eigen::Vector3d(0.5, 0, 0);  // along a's x, which is the world's y
  ahead.angular = Eigen::Vector3d(0.2, 0, 0);
  world.setModelState("b", ahead, "a");
  const EntityState b = world.modelState("b");
  EXPECT_TRUE(b.pose.translation().isApprox(Eigen::Vector3d(1, 3, 1), 1e-9));
  EXPECT_NEAR(yawOf(b.pose), M_PI / 2, 1e-9);
  EXPECT_TRUE(b.linear.isApprox(Eigen::Vector3d(0, 0.5, 0), 1e-9));
  EXPECT_TRUE(b.angular.isApprox(Eigen::Vector3d(0, 0.2, 0), 1e-9));
  // Read back relative to a, velocities come back in a's axes (a is at rest).
  const EntityState back = world.modelState("b", "a");
  EXPECT_TRUE(back.linear.isApprox(ahead.linear, 1e-9));

  EXPECT_THAT([&] { world.modelState("b", "a::base_lnk"); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("(did you mean [a::base_link]?)")));
  EXPECT_THAT([&] { world.modelState("c"); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("no model [c]")));
}

TEST(Entities, ALinkStateMovesItsRobotByTheRootPartOnly) {
  Simulation simulation(crateWorld(/*weightless=*/true));
  WorldApi world(simulation);
  simulation.spawn("robot", twoWheeler("contact"), {.z = 1});
  const EntityState link = at(-2, 1, 0.5, 0.3);
  world.setLinkState("robot::base_link", link);
  EXPECT_TRUE(world.linkState("robot::base_link").pose.isApprox(link.pose, 1e-9));
  EXPECT_TRUE(world.modelState("robot").pose.translation().isApprox(Eigen::Vector3d(-2, 1, 0.45), 1e-9));
  EXPECT_THAT(
      [&] { world.setLinkState("robot::left_wheel", link); },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("moves on joint [left_wheel_joint]")));
  world.setLinkState("crate::body", at(0, 3, 0.5, 0));
  EXPECT_TRUE(world.modelState("crate").pose.translation().isApprox(Eigen::Vector3d(0, 3, 0.5)));
}

TEST(Entities, AWrenchForDurationTChangesAFreeBodysVelocityByForceTimesTOverMass) {
  Simulation simulation(crateWorld(/*weightless=*/true));
  WorldApi world(simulation);
  simulation.spawn("box", fixtureRobot("minimal.urdf"), {.z = 3});  // 1 kg, its centre of mass at its origin
  const Eigen::Vector3d force(2, -1, 0.5);
  const double duration = 0.25;
  BodyWrench wrench{"box::base_link",        "",
                    Eigen::Vector3d::Zero(), force,
                    Eigen::Vector3d::Zero(), {simulation.time() + 0.1, duration}};
  EXPECT_EQ(world.applyBodyWrench(wrench), "");
  for (int i = 0; i < 100; ++i) simulation.step();
  EXPECT_TRUE(world.modelState("box").linear.isZero()) << "it starts at start_time";
  for (int i = 0; i < 400; ++i) simulation.step();
  EXPECT_LT((world.modelState("box").linear - force * duration / 1.0).norm(), 1e-9);

  // Until cleared, in the axes of a reference frame, with its point off the centre of mass.
  world.setModelState("box", at(0, 0, 3, M_PI / 2));
  wrench = {
      "box",  "box::base_link", Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero(),
      {0, -1}};
  world.applyBodyWrench(wrench);
  for (int i = 0; i < 100; ++i) simulation.step();
  world.clearBodyWrenches("box::base_link");
  for (int i = 0; i < 100; ++i) simulation.step();
  const EntityState box = world.modelState("box");
  EXPECT_TRUE(box.linear.isApprox(Eigen::Vector3d(0, 0.1, 0), 1e-9))
      << "1 N along the box's x, world y, 0.1 s";
  // The force 0.1 m above the centre of mass, along world y: a moment of 0.1 N m about world -x.
  EXPECT_TRUE(box.angular.isApprox(Eigen::Vector3d(-0.1 * 0.1 / 0.01, 0, 0), 1e-6))
      << box.angular.transpose();
  EXPECT_THAT(world.applyBodyWrench({"box", "", {}, force, {}, {0, 0}}),
              HasSubstr("nothing is applied"));
  EXPECT_THAT(
      [&] {
        world.applyBodyWrench({"crate::body", "", {}, force, {}, {0, 1}});
      },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("static")));
}

TEST(Entities, AScheduledWrenchGoesWithItsRobotAndWithTheWorldApiThatScheduledIt) {
  Simulation simulation(crateWorld(/*weightless=*/true));
  const BodyWrench push{"box", "", {}, Eigen::Vector3d(1, 0, 0), {}, {0, -1}};  // until cleared
  WorldApi world(simulation);
  simulation.spawn("box", fixtureRobot("minimal.urdf"), {.z = 3});
  world.applyBodyWrench(push);
  simulation.remove("box");
  simulation.spawn("box", fixtureRobot("minimal.urdf"), {.z = 3});
  for (int i = 0; i < 100; ++i) simulation.step();
  EXPECT_TRUE(world.modelState("box").linear.isZero()) << "a new robot of the removed one's name";
  {
    WorldApi gone(simulation);
    gone.applyBodyWrench(push);
  }
  for (int i = 0; i < 100; ++i) simulation.step();
  EXPECT_TRUE(world.modelState("box").linear.isZero()) << "the world API that scheduled it is gone";
  world.applyBodyWrench(push);
  for (int i = 0; i < 100; ++i) simulation.step();
  EXPECT_NEAR(world.modelState("box").linear.x(), 1 * 0.1 / 1.0, 1e-9) << "1 N on 1 kg for 0.1 s";
}

TEST(Entities, AJointEffortForDurationTSpinsAFreeWheelByEffortTimesTOverItsInertia) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(crateWorld(/*weightless=*/true));
    WorldApi world(simulation);
    Robot& robot = simulation.spawn("robot", twoWheeler(wheel_model, "1e-12"), {.z = 1});
    const double effort = 0.01, duration = 0.2, inertia = 2.5e-4;  // the wheel's about its axle
    EXPECT_EQ(world.applyJointEffort({"robot::left_wheel_joint", effort, {0, duration}}), "");
    for (int i = 0; i < 400; ++i) simulation.step();
    // The axle pushes through the wheel's centre, so only the effort turns it about its own centre.
    EXPECT_NEAR(robot.body().linkAngularVelocity("left_wheel").y(), effort * duration / inertia, 1e-6);
    EXPECT_THAT(world.applyJointEffort({"left_wheel_joint", effort, {0, 1e-4}}),
                HasSubstr("applied for one step"));
    world.clearJointEfforts("left_wheel_joint");
  }
  Simulation simulation(test::shippedWorld("empty.world"));
  WorldApi world(simulation);
  simulation.spawn("car", test::yahboomcar("raycast"), {});
  EXPECT_THAT(
      [&] {
        world.applyJointEffort({"car::jq1_Joint", 0.1, {0, 1}});
      },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("<wheelModel>contact</wheelModel>")));
}

TEST(Entities, AModelConfigurationSetsTheNamedJointsOnly) {
  Simulation simulation(test::shippedWorld("empty.world"));
  WorldApi world(simulation);
  Robot& robot = simulation.spawn("robot", twoWheeler("contact"), {.x = 1});
  const Eigen::Isometry3d root = robot.body().linkPose("base_footprint");
  world.setModelConfiguration("robot", {{"left_wheel_joint", 1.0}});
  EXPECT_NEAR(world.jointProperties("robot::left_wheel_joint").position, 1.0, 1e-12);
  EXPECT_NEAR(world.jointProperties("right_wheel_joint").position, 0.0, 1e-12);
  EXPECT_TRUE(robot.body().linkPose("base_footprint").isApprox(root, 1e-12));
  // As Gazebo, an unknown joint is skipped, the others set; the note names it.
  EXPECT_THAT(
      world.setModelConfiguration("robot", {{"left_wheel_jiont", 2.0}, {"right_wheel_joint", 0.5}}),
      HasSubstr("[left_wheel_jiont] is not a moving joint of [robot] (did you mean [left_wheel_joint]?)"));
  EXPECT_NEAR(world.jointProperties("robot::left_wheel_joint").position, 1.0, 1e-12);
  EXPECT_NEAR(world.jointProperties("right_wheel_joint").position, 0.5, 1e-12);
  EXPECT_EQ(world.setModelConfiguration("robot", {{"left_wheel_joint", 0.0}}), "");
  EXPECT_THAT(
      [&] {
        world.setModelConfiguration("ground_plane", {{"x", 1.0}});
      },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("the world's")));
}

TEST(Entities, PropertiesAreGazebosForRobotsAndWorldModels) {
  Simulation simulation(crateWorld());
  WorldApi world(simulation);
  simulation.spawn("robot", twoWheeler("contact"), {});
  const ModelProperties robot = world.modelProperties("robot");
  EXPECT_THAT(robot.body_names, ElementsAre("base_footprint", "left_wheel", "right_wheel"));
  EXPECT_THAT(robot.geom_names, ElementsAre("base_footprint_fixed_joint_lump__base_link_collision",
                                            "base_footprint_fixed_joint_lump__caster_collision_1",
                                            "left_wheel_collision", "right_wheel_collision"));
  EXPECT_THAT(robot.joint_names, ElementsAre("left_wheel_joint", "right_wheel_joint"));
  EXPECT_FALSE(robot.is_static);
  const ModelProperties crate = world.modelProperties("crate");
  EXPECT_THAT(crate.body_names, ElementsAre("body"));
  EXPECT_THAT(crate.geom_names, ElementsAre("box"));
  EXPECT_TRUE(crate.is_static);

  const LinkProperties base = world.linkProperties("robot::base_link");
  EXPECT_DOUBLE_EQ(base.mass, 2.0);
  EXPECT_TRUE(base.com.isApprox(Eigen::Vector3d(0, 0, 0.05)));
  EXPECT_DOUBLE_EQ(base.inertia(2, 2), 0.0417);
  EXPECT_TRUE(base.gravity);
  const JointProperties wheel = world.jointProperties("left_wheel_joint");
  EXPECT_EQ(wheel.type, JointSpec::Type::kContinuous);
  EXPECT_THAT([&] { world.jointProperties("caster_joint"); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("is fixed")));
}

TEST(Entities, PhysicsPropertiesChangeTheStepAndGravityFromTheNextStepOn) {
  Simulation simulation(test::shippedWorld("empty.world"));
  WorldApi world(simulation);
  Robot& box = simulation.spawn("box", fixtureRobot("minimal.urdf"), {.z = 10});
  EXPECT_DOUBLE_EQ(world.physicsProperties().step_size, 0.001);
  EXPECT_DOUBLE_EQ(world.physicsProperties().gravity.z(), -9.81);
  for (int i = 0; i < 100; ++i) simulation.step();
  const double before = simulation.time();
  world.setModelState("box", at(0, 0, 10, 0));  // at rest again
  world.setPhysicsProperties({0.004, 0, Eigen::Vector3d(0, 0, -1.62)});
  const int n = 250;
  for (int i = 0; i < n; ++i) simulation.step();
  EXPECT_NEAR(simulation.time(), before + n * 0.004, 1e-12);
  // Free fall under symplectic Euler: after n steps of dt, g dt^2 n (n + 1) / 2.
  const double fallen = 10 - box.body().linkPose("base_link").translation().z();
  EXPECT_NEAR(fallen, 1.62 * 0.004 * 0.004 * n * (n + 1) / 2, 1e-9);
  const PhysicsProperties now = world.physicsProperties();
  EXPECT_DOUBLE_EQ(now.step_size, 0.004);
  EXPECT_DOUBLE_EQ(now.max_update_rate, 0);
  EXPECT_THAT(
      [&] {
        world.setPhysicsProperties({0, 1000, Eigen::Vector3d::Zero()});
      },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("must be positive")));
  EXPECT_DOUBLE_EQ(simulation.stepSize(), 0.004) << "a refused change changes nothing";
  simulation.resetSimulation();
  simulation.step();
  EXPECT_DOUBLE_EQ(simulation.time(), 0.004) << "after a reset, time restarts at the first step";
}

TEST(Entities, RequestsBeyondWhatCanBeSimulatedAreRefusedAndChangeNothing) {
  Simulation simulation(crateWorld());
  WorldApi world(simulation);
  simulation.spawn("box", fixtureRobot("minimal.urdf"), {.z = 1});
  const Eigen::Isometry3d before = world.modelState("box").pose;
  EntityState far = at(1e300, 0, 0, 0);
  EXPECT_THAT([&] { world.setModelState("box", far); },
              ::testing::ThrowsMessage<std::invalid_argument>(
                  HasSubstr("model [box]: pose.position.x [1e+300] m is beyond")));
  EXPECT_THAT([&] { world.setModelState("crate", at(0, 2e4, 0, 0)); },
              ::testing::ThrowsMessage<std::invalid_argument>(
                  HasSubstr("[20000] m is beyond the limit of 10000 m (max_length)")));
  EntityState fast = at(0, 0, 1, 0);
  fast.linear.x() = NAN;
  EXPECT_THAT([&] { world.setModelState("box", fast); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("not finite")));
  EXPECT_THAT(
      [&] {
        world.applyBodyWrench({"box", "", {}, Eigen::Vector3d(1e300, 0, 0), {}, {0, 1}});
      },
      ::testing::ThrowsMessage<std::invalid_argument>(
          HasSubstr("the wrench on [box]: wrench.force.x [1e+300 N] is beyond")));
  EXPECT_THAT(
      [&] {
        world.setPhysicsProperties({10, 1000, Eigen::Vector3d(0, 0, -9.81)});
      },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("time_step [10 s] is beyond")));
  EXPECT_THAT([&] { simulation.spawn("far", fixtureRobot("minimal.urdf"), {.x = 1e300}); },
              ::testing::ThrowsMessage<SpecError>(HasSubstr("spawn pose x [1e+300] m is beyond the limit")));
  for (int i = 0; i < 100; ++i) simulation.step();  // nothing was changed, and it runs on
  EXPECT_NEAR(world.modelState("box").pose.translation().x(), before.translation().x(), 1e-9);
  EXPECT_TRUE(world.modelState("crate").pose.translation().isApprox(Eigen::Vector3d(2, 0, 0.5)));
}

}  // namespace
}  // namespace bullet_sim
