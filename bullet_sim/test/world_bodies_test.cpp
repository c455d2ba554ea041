// A world's non-static model is a body with its mass, jointed as its file says: robots push it, sensors see
// it where it is now, reset_world puts it back, and the world API lists and moves it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/world_api.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::Contains;
using ::testing::HasSubstr;

// [m] the crate's side: the lidar mast's beams, 0.5 m up, reach it, and the wheelchair cannot straddle it
// (its drive wheels are 0.604 m apart inside: a 0.6 m crate jammed between them like a drawer)
constexpr double kCrate = 0.8;

/// A ground plane and a crate of kCrate and `mass` [kg] at (2, 0) resting on it; `extra` is more SDF inside
/// the world.
WorldSpec crateWorld(std::vector<std::string>* warnings = nullptr, const std::string& extra = "",
                     double mass = 1) {
  const std::string side = std::to_string(kCrate);
  const std::string box = "<box><size>" + side + " " + side + " " + side + "</size></box>";
  const std::string moment = std::to_string(mass * kCrate * kCrate / 6);  // a solid cube's
  const std::string sdf =
      "<sdf version='1.6'><world name='crates'>"
      "<model name='ground_plane'><static>true</static><link name='link'><collision name='collision'>"
      "<geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry></collision></link>"
      "</model><model name='crate'><pose>2 0 " + std::to_string(kCrate / 2) + " 0 0 0</pose>"
      "<link name='link'><inertial><mass>" + std::to_string(mass) + "</mass><inertia><ixx>" +
      moment + "</ixx><iyy>" + moment +
      "</iyy><izz>" + moment + "</izz></inertia></inertial>"
      "<collision name='collision'><geometry>" + box + "</geometry></collision>"
      "<visual name='visual'><geometry>" + box + "</geometry></visual></link></model>" + extra +
      "</world></sdf>";
  return parseWorld(sdf, "crates.world", PackageResolver::fromEnvironment(), warnings);
}

Eigen::Vector3d crateAt(const WorldApi& world) {
  return world.modelState("crate").pose.translation();
}

TEST(WorldBodies, ANonStaticModelLoadsWithoutWarningAndIsListed) {
  std::vector<std::string> warnings;
  Simulation simulation(crateWorld(&warnings));
  WorldApi world(simulation);
  EXPECT_THAT(warnings, ::testing::IsEmpty());
  EXPECT_FALSE(world.modelProperties("crate").is_static);
  EXPECT_THAT(world.modelNames(), Contains("crate"));
  EXPECT_NEAR(world.linkProperties("crate::link").mass, 1.0, 1e-12);
}

TEST(WorldBodies, ItFallsUnderGravityAndResetWorldPutsItBack) {
  Simulation simulation(crateWorld());
  WorldApi world(simulation);
  EntityState lifted;
  const double height = kCrate / 2 + 1.0;  // [m] 1 m above its rest
  lifted.pose.translation() = Eigen::Vector3d(2, 0, height);
  EXPECT_EQ(world.setModelState("crate", lifted), "");
  EXPECT_NEAR(crateAt(world).z(), height, 1e-9) << "set_model_state moves it";
  for (int i = 0; i < 1000; ++i) simulation.step();
  EXPECT_NEAR(crateAt(world).z(), kCrate / 2, 0.005) << "it fell 1 m and rests on the ground";
  simulation.resetWorld();
  EXPECT_TRUE(crateAt(world).isApprox(Eigen::Vector3d(2, 0, kCrate / 2), 1e-9));
  EXPECT_NEAR(world.modelState("crate").linear.norm(), 0, 1e-12);
}

// Touching nothing, the crate's island has no contact for the solver: its forces reach its velocities
// directly (physics/islands.cpp's IslandSolver), and must do so as Newton and Euler say.
// However heavy, up to our largest link mass, it rests where it was put: its contacts' compliance let a
// 1e5 kg crate close on the ground faster than a contact's depth is corrected.
TEST(WorldBodies, AHeavyCrateRestsOnTheGround) {
  for (double mass : {1e3, 1e5, 1e6}) {
    Simulation simulation(crateWorld(nullptr, "", mass));
    WorldApi world(simulation);
    for (int i = 0; i < 1000; ++i) simulation.step();
    EXPECT_NEAR(crateAt(world).z(), kCrate / 2, 1e-3) << mass << " kg";
  }
}

TEST(WorldBodies, InTheAirItMovesAsNewtonAndEulerSay) {
  Simulation simulation(crateWorld(nullptr, "<gravity>0 0 -9.81</gravity>"));
  WorldApi world(simulation);
  EntityState thrown;
  thrown.pose.translation() = Eigen::Vector3d(2, 0, 50);
  thrown.linear = Eigen::Vector3d(1, -0.5, 2);
  thrown.angular = Eigen::Vector3d(0, 0, 3);  // about a principal axis of a cube: no gyroscopic torque
  ASSERT_EQ(world.setModelState("crate", thrown), "");
  const Eigen::Vector3d force(4, 0, 0);     // [N]
  const Eigen::Vector3d torque(0, 0, 0.2);  // [N m]
  const double seconds = 0.5;
  ASSERT_EQ(world.applyBodyWrench({"crate", "", {}, force, torque, {0, -1}}), "");  // until cleared
  const int steps = static_cast<int>(std::lround(seconds / simulation.stepSize()));
  for (int i = 0; i < steps; ++i) simulation.step();
  const EntityState now = world.modelState("crate");
  // mass and inertia as the file writes them
  const LinkProperties crate = world.linkProperties("crate::link");
  const Eigen::Vector3d acceleration = force / crate.mass + Eigen::Vector3d(0, 0, -9.81);
  EXPECT_LT((now.linear - (thrown.linear + acceleration * seconds)).norm(), 1e-9) << now.linear.transpose();
  const double inertia = crate.inertia(2, 2);  // [kg m^2]
  EXPECT_NEAR(now.angular.z(), 3 + torque.z() / inertia * seconds, 1e-9);
  EXPECT_NEAR(now.angular.head<2>().norm(), 0, 1e-12);
  // Semi-implicit Euler: the position takes each step's new velocity, half a step's worth ahead of the exact
  // parabola.
  const Eigen::Vector3d exact =
      thrown.pose.translation() + thrown.linear * seconds + acceleration * seconds * seconds / 2;
  const Eigen::Vector3d stepped = exact + acceleration * seconds * simulation.stepSize() / 2;
  EXPECT_LT((now.pose.translation() - stepped).norm(), 1e-9) << now.pose.translation().transpose();
}

/// A loose ball of 1 kg and radius 0.4 m named `name`, its centre at x, y and 50 m up.
std::string highBall(const std::string& name, double x, double y) {
  return "<model name='" + name + "'><pose>" + std::to_string(x) + " " + std::to_string(y) +
         " 50 0 0 0</pose><link name='link'><inertial><mass>1</mass></inertial><collision name='c'>"
         "<geometry><sphere><radius>0.4</radius></sphere></geometry></collision></link></model>";
}

// Two balls falling side by side, 0.7 m apart along x and y: their bounds (cubes of 0.8 m) overlap, so
// Bullet keeps a manifold for the pair, and they do not touch (0.19 m apart), so they are two islands.
// Each falls as Newton says: the manifold without points joins neither island's solve to the other's
// (the solve given it would add the other ball's gravity a second time each step).
TEST(WorldBodies, BallsWhoseBoundsOverlapWithoutTouchingFallAsNewtonSays) {
  Simulation simulation(crateWorld(nullptr, "<gravity>0 0 -9.81</gravity>" + highBall("ball1", -3, 0) +
                                                highBall("ball2", -2.3, 0.7)));
  WorldApi world(simulation);
  const double seconds = 0.5;
  for (int i = 0; i < std::lround(seconds / simulation.stepSize()); ++i) simulation.step();
  for (const std::string name : {"ball1", "ball2"}) {
    SCOPED_TRACE(name);
    const EntityState now = world.modelState(name);
    EXPECT_LT((now.linear - Eigen::Vector3d(0, 0, -9.81 * seconds)).norm(), 1e-9) << now.linear.transpose();
    EXPECT_NEAR(now.angular.norm(), 0, 1e-12);
  }
}

TEST(WorldBodies, ARobotPushesItAndALidarSeesItWhereItIsNow) {
  Simulation simulation(crateWorld());
  WorldApi world(simulation);
  Robot& chair = simulation.spawn("chair", test::wheelchair(), {});
  Robot& mast = simulation.spawn(
      "mast", test::parseQuietly(test::readFile(test::fixture("robots/lidar_mast.urdf")), "mast"),
      {.x = 3, .y = -2, .yaw = M_PI / 2});
  auto* drive = test::pluginsOf<WheeledDrive>(chair).at(0);
  for (int i = 0; i < 8000 && crateAt(world).x() < 3; ++i) {
    if (i % 100 == 0) drive->setCommand(0.5, 0, simulation.time());
    simulation.step();
  }
  const Eigen::Vector3d crate = crateAt(world);
  ASSERT_GT(crate.x(), 3) << "pushed on by the chair from x = 2";
  const LaserScan& scan = mast.outputs<LaserScan>().at(0).stream->latest();
  int on_crate = 0;  // returns on the crate's faces where it is now
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!std::isfinite(scan.ranges[i])) continue;
    const double angle = scan.angle_min + i * scan.angle_increment;
    const Eigen::Vector3d hit =
        scan.sensor_pose * (scan.ranges[i] * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0));
    const Eigen::Vector3d in_crate = world.modelState("crate").pose.inverse() * hit;
    on_crate += (in_crate.cwiseAbs().array() <= kCrate / 2 + 0.01).all();
  }
  EXPECT_GT(on_crate, 3);
}

// A door as Gazebo worlds write one: a frame fixed to the world and a 10 kg leaf of 1 m on a vertical hinge
// at x = 2, y = 0.5, opening (0 to 90 degrees) away from a robot coming from the origin along +x.
constexpr double kDoorOpen = M_PI / 2;  // [rad] the hinge's upper limit
const std::string kDoor = R"(
  <model name='door'><pose>2 0.5 0 0 0 0</pose>
    <link name='frame'><pose>0 0.06 1 0 0 0</pose>
      <collision name='post'><geometry><box><size>0.1 0.1 2</size></box></geometry></collision>
      <visual name='post'><geometry><box><size>0.1 0.1 2</size></box></geometry></visual></link>
    <link name='leaf'>
      <inertial><pose>0 -0.5 0.95 0 0 0</pose><mass>10</mass>
        <inertia><ixx>3.53</ixx><iyy>2.70</iyy><izz>0.835</izz></inertia></inertial>
      <collision name='panel'><pose>0 -0.5 0.95 0 0 0</pose>
        <geometry><box><size>0.05 1 1.8</size></box></geometry></collision>
      <visual name='panel'><pose>0 -0.5 0.95 0 0 0</pose>
        <geometry><box><size>0.05 1 1.8</size></box></geometry></visual></link>
    <joint name='fixed_to_world' type='fixed'><parent>world</parent><child>frame</child></joint>
    <joint name='hinge' type='revolute'><parent>frame</parent><child>leaf</child>
      <axis><xyz>0 0 1</xyz><limit><lower>0</lower><upper>1.5707963</upper></limit>
        <dynamics><damping>2</damping></dynamics></axis></joint>
  </model>)";

/// Where the leaf's panel is now: its centre's frame.
Eigen::Isometry3d panelPose(const WorldApi& world) {
  return world.linkState("door::leaf").pose * Eigen::Translation3d(0, -0.5, 0.95);
}

/// How many of a scan's returns lie on a box of `size` at `pose` (within 1 cm).
int returnsOn(const LaserScan& scan, const Eigen::Isometry3d& pose, const Eigen::Vector3d& size) {
  int on = 0;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!std::isfinite(scan.ranges[i])) continue;
    const double angle = scan.angle_min + i * scan.angle_increment;
    const Eigen::Vector3d hit =
        scan.sensor_pose * (scan.ranges[i] * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0));
    on += ((pose.inverse() * hit).cwiseAbs().array() <= size.array() / 2 + 0.01).all();
  }
  return on;
}

TEST(WorldBodies, ADoorIsAMultibodyThatARobotSwingsOpenWithinItsLimits) {
  std::vector<std::string> warnings;
  Simulation simulation(crateWorld(&warnings, kDoor));
  WorldApi world(simulation);
  EXPECT_THAT(warnings, ::testing::IsEmpty());
  const ModelProperties door = world.modelProperties("door");
  EXPECT_FALSE(door.is_static);
  EXPECT_THAT(door.body_names, ::testing::ElementsAre("frame", "leaf"));
  EXPECT_THAT(door.geom_names, ::testing::ElementsAre("post", "panel"));
  EXPECT_THAT(door.joint_names, ::testing::ElementsAre("fixed_to_world", "hinge"));
  EXPECT_NEAR(world.jointProperties("door::hinge").upper, kDoorOpen, 1e-6);
  EXPECT_NEAR(world.linkProperties("door::leaf").mass, 10, 1e-12);
  const Eigen::Isometry3d closed = panelPose(world);

  Robot& chair = simulation.spawn("chair", test::wheelchair(), {});
  auto* drive = test::pluginsOf<WheeledDrive>(chair).at(0);
  double widest = 0;  // [rad] the hinge's largest angle
  for (int i = 0; i < 12000 && world.jointProperties("door::hinge").position < 1.0; ++i) {
    if (i % 100 == 0) drive->setCommand(0.5, 0, simulation.time());
    simulation.step();
    widest = std::max(widest, world.jointProperties("door::hinge").position);
    ASSERT_GT(world.jointProperties("door::hinge").position, -0.01) << "the lower limit holds";
  }
  ASSERT_GT(widest, 1.0) << "pushed open by the chair";
  EXPECT_LT(widest, kDoorOpen + 0.02) << "within its upper limit";
  EXPECT_TRUE(world.linkState("door::frame")
                  .pose.isApprox(Eigen::Isometry3d(Eigen::Translation3d(2, 0.56, 1)), 1e-6))
      << "the frame is fixed to the world";
  const Eigen::Vector3d hinge = world.linkState("door::leaf").pose.translation();
  EXPECT_LT((hinge - Eigen::Vector3d(2, 0.5, 0)).norm(), 1e-3) << "the leaf turns about its hinge";

  // A lidar beside the door sees the leaf where it is now, not where it was.
  Robot& mast = simulation.spawn(
      "mast", test::parseQuietly(test::readFile(test::fixture("robots/lidar_mast.urdf")), "mast"),
      {.x = 2.6, .y = 2.2, .yaw = -M_PI / 2});
  for (int i = 0; i < 200; ++i) simulation.step();
  const LaserScan& scan = mast.outputs<LaserScan>().at(0).stream->latest();
  const Eigen::Vector3d panel(0.05, 1, 1.8);
  EXPECT_GT(returnsOn(scan, panelPose(world), panel), 5);
  EXPECT_EQ(returnsOn(scan, closed, panel), 0);

  // Cameras draw it there too: its visual's frame turned with the leaf.
  const size_t door_model = 2;  // after the ground and the crate
  ASSERT_EQ(simulation.world().models.at(door_model).name, "door");
  const Visual& leaf_visual = simulation.world().models[door_model].visuals.at(1);
  EXPECT_TRUE((simulation.worldVisualFrame(door_model, 1) * leaf_visual.origin)
                  .isApprox(panelPose(world), 1e-9));

  simulation.resetWorld();
  EXPECT_NEAR(world.jointProperties("door::hinge").position, 0, 1e-12) << "reset_world closes it";
  EXPECT_TRUE(panelPose(world).isApprox(closed, 1e-9));
}

// Two links on a fixed joint, not fixed to the world: one rigid body, which falls, is moved and is listed as
// Gazebo lists an SDF model's links.
TEST(WorldBodies, TwoLinksOnAFixedJointMoveAsOne) {
  const std::string dumbbell = R"(
    <model name='dumbbell'><pose>-2 0 0.1 0 0 0</pose>
      <link name='a'><collision name='ball'><geometry><sphere><radius>0.1</radius></sphere></geometry></collision></link>
      <link name='b'><pose>0 1 0 0 0 0</pose>
        <collision name='ball'><geometry><sphere><radius>0.1</radius></sphere></geometry></collision></link>
      <joint name='bar' type='fixed'><parent>a</parent><child>b</child></joint>
    </model>)";
  std::vector<std::string> warnings;
  Simulation simulation(crateWorld(&warnings, dumbbell));
  WorldApi world(simulation);
  EXPECT_THAT(warnings, ::testing::IsEmpty());
  EXPECT_FALSE(world.modelProperties("dumbbell").is_static);
  const auto b_in_a = [&] {
    return world.linkState("dumbbell::a").pose.inverse() * world.linkState("dumbbell::b").pose;
  };
  EntityState lifted;
  lifted.pose = Eigen::Translation3d(-2, 0, 1.1) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
  world.setModelState("dumbbell", lifted);
  EXPECT_TRUE(world.linkState("dumbbell::b")
                  .pose.translation()
                  .isApprox(Eigen::Vector3d(-2, std::cos(0.3), 1.1 + std::sin(0.3)), 1e-9))
      << "set_model_state moves both links";
  world.setModelState("dumbbell", {Eigen::Isometry3d(Eigen::Translation3d(-2, 0, 1.1))});
  for (int i = 0; i < 1000; ++i) simulation.step();
  EXPECT_NEAR(world.linkState("dumbbell::a").pose.translation().z(), 0.1, 0.005) << "it fell 1 m";
  EXPECT_NEAR(world.linkState("dumbbell::b").pose.translation().z(), 0.1, 0.005);
  EXPECT_TRUE(b_in_a().isApprox(Eigen::Isometry3d(Eigen::Translation3d(0, 1, 0)), 1e-6)) << "rigidly";
  std::vector<std::string> links;
  for (const NamedState& state : world.linkStates()) links.push_back(state.name);
  EXPECT_THAT(links, ::testing::IsSupersetOf({"dumbbell::a", "dumbbell::b"}));
}

TEST(WorldBodies, WhatBulletSimCannotSimulateGetsOneWarningSayingWhatItDoesInstead) {
  const std::string ball =
      "<model name='lamp'><pose>-2 2 1 0 0 0</pose><link name='arm'><collision name='c'><geometry>"
      "<sphere><radius>0.1</radius></sphere></geometry></collision></link>"
      "<link name='shade'><pose>0 0 -0.3 0 0 0</pose>"
      "<collision name='c'><geometry><sphere><radius>0.1</radius></sphere></geometry></collision></link>"
      "<joint name='swivel' type='ball'><parent>arm</parent><child>shade</child></joint>"
      "<joint name='hook' type='fixed'><parent>world</parent><child>arm</child></joint></model>";
  const std::string loop =
      "<model name='ring'><pose>-2 -2 1 0 0 0</pose><link name='a'/><link name='b'/>"
      "<joint name='ab' type='revolute'><parent>a</parent><child>b</child>"
      "<axis><xyz>0 0 1</xyz></axis></joint>"
      "<joint name='ba' type='revolute'><parent>b</parent><child>a</child>"
      "<axis><xyz>0 0 1</xyz></axis></joint>"
      "</model>";
  std::vector<std::string> warnings;
  Simulation simulation(crateWorld(&warnings, ball + loop));
  WorldApi world(simulation);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_THAT(warnings[0], HasSubstr("joint [swivel]: type [ball] is not simulated"));
  EXPECT_THAT(warnings[0], HasSubstr("held fixed"));
  EXPECT_FALSE(world.modelProperties("lamp").is_static);
  EXPECT_THAT(warnings[1],
              HasSubstr("model [ring] is not static, but bullet_sim cannot simulate it as a body"));
  EXPECT_THAT(warnings[1], HasSubstr("loop"));
  EXPECT_THAT(warnings[1], HasSubstr("static obstacle"));
  EXPECT_TRUE(world.modelProperties("ring").is_static);
}

}  // namespace
}  // namespace bullet_sim
