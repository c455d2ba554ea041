// A world's non-static model is a rigid body with its mass: robots push it, sensors see it where it is now,
// reset_world puts it back, and the world API lists and moves it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bullet_sim/plugins/ray_lidar.h"
#include "bullet_sim/plugins/wheeled_drive.h"
#include "bullet_sim/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::Contains;
using ::testing::HasSubstr;

constexpr double kCrate = 0.6;  // [m] the crate's side: the lidar mast's beams, 0.5 m up, reach it

/// A ground plane and a 1 kg crate of 0.6 m at (2, 0) resting on it; `extra` is more SDF inside the world.
WorldSpec crateWorld(std::vector<std::string>* warnings = nullptr, const std::string& extra = "") {
  const std::string box = "<box><size>0.6 0.6 0.6</size></box>";
  const std::string sdf =
      "<sdf version='1.6'><world name='crates'>"
      "<model name='ground_plane'><static>true</static><link name='link'><collision name='collision'>"
      "<geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry></collision></link>"
      "</model><model name='crate'><pose>2 0 0.3 0 0 0</pose><link name='link'><inertial><mass>1</mass>"
      "<inertia><ixx>0.06</ixx><iyy>0.06</iyy><izz>0.06</izz></inertia></inertial>"
      "<collision name='collision'><geometry>" + box + "</geometry></collision>"
      "<visual name='visual'><geometry>" + box + "</geometry></visual></link></model>" + extra +
      "</world></sdf>";
  return parseWorld(sdf, "crates.world", PackageResolver::fromEnvironment(), warnings);
}

Eigen::Vector3d crateAt(const Simulation& simulation) {
  return simulation.modelState("crate").pose.translation();
}

TEST(WorldBodies, ANonStaticModelLoadsWithoutWarningAndIsListed) {
  std::vector<std::string> warnings;
  Simulation simulation(crateWorld(&warnings));
  EXPECT_THAT(warnings, ::testing::IsEmpty());
  EXPECT_FALSE(simulation.modelProperties("crate").is_static);
  EXPECT_THAT(simulation.modelNames(), Contains("crate"));
  EXPECT_NEAR(simulation.linkProperties("crate::link").mass, 1.0, 1e-12);
}

TEST(WorldBodies, ItFallsUnderGravityAndResetWorldPutsItBack) {
  Simulation simulation(crateWorld());
  EntityState lifted;
  lifted.pose.translation() = Eigen::Vector3d(2, 0, 1.2);
  EXPECT_EQ(simulation.setModelState("crate", lifted), "");
  EXPECT_NEAR(crateAt(simulation).z(), 1.2, 1e-9) << "set_model_state moves it";
  for (int i = 0; i < 1000; ++i) simulation.step();
  EXPECT_NEAR(crateAt(simulation).z(), kCrate / 2, 0.005) << "it fell 1 m and rests on the ground";
  simulation.resetWorld();
  EXPECT_TRUE(crateAt(simulation).isApprox(Eigen::Vector3d(2, 0, 0.3), 1e-9));
  EXPECT_NEAR(simulation.modelState("crate").linear.norm(), 0, 1e-12);
}

TEST(WorldBodies, ARobotPushesItAndALidarSeesItWhereItIsNow) {
  Simulation simulation(crateWorld());
  Robot& chair = simulation.spawn("chair", test::wheelchair(), {});
  Robot& mast = simulation.spawn(
      "mast", test::parseQuietly(test::readFile(test::fixture("robots/lidar_mast.urdf")), "mast"),
      {.x = 3, .y = -2, .yaw = M_PI / 2});
  auto* drive = chair.pluginsOf<WheeledDrive>().at(0);
  for (int i = 0; i < 8000 && crateAt(simulation).x() < 3; ++i) {
    if (i % 100 == 0) drive->setCommand(0.5, 0, simulation.time());
    simulation.step();
  }
  const Eigen::Vector3d crate = crateAt(simulation);
  ASSERT_GT(crate.x(), 3) << "pushed on by the chair from x = 2";
  const LaserScan& scan = mast.pluginsOf<RayLidar>().at(0)->scan();
  int on_crate = 0;  // returns on the crate's faces where it is now
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!std::isfinite(scan.ranges[i])) continue;
    const double angle = scan.angle_min + i * scan.angle_increment;
    const Eigen::Vector3d hit = scan.sensor_pose * (scan.ranges[i] * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0));
    const Eigen::Vector3d in_crate = simulation.modelState("crate").pose.inverse() * hit;
    on_crate += (in_crate.cwiseAbs().array() <= kCrate / 2 + 0.01).all();
  }
  EXPECT_GT(on_crate, 3);
}

TEST(WorldBodies, AMultiLinkModelIsStaticWithOneWarningSayingSo) {
  const std::string door =
      "<model name='door'><link name='frame'><collision name='c'><geometry><box><size>0.1 0.1 2</size></box>"
      "</geometry></collision></link><link name='leaf'><pose>0.5 0 1 0 0 0</pose><collision name='c'>"
      "<geometry><box><size>0.9 0.05 2</size></box></geometry></collision></link>"
      "<joint name='hinge' type='revolute'><parent>frame</parent><child>leaf</child><axis><xyz>0 0 1</xyz>"
      "</axis></joint></model>";
  std::vector<std::string> warnings;
  Simulation simulation(crateWorld(&warnings, door));
  EXPECT_TRUE(simulation.modelProperties("door").is_static);
  int about_door = 0;
  for (const auto& warning : warnings) about_door += warning.find("[door]") != std::string::npos;
  EXPECT_EQ(about_door, 1);
  EXPECT_THAT(warnings.at(0), HasSubstr("static obstacle"));
}

}  // namespace
}  // namespace bullet_sim
