// Friction between two surfaces is the lesser of their mu, as Gazebo's ODE contacts take it: a world's
// <surface><friction><ode><mu>, a URDF link's <mu1>, each collision its own, even where links are fixed
// into one body, and a wheel's on either wheel model. A crate sent sliding at v stops after v^2 / (2 mu g);
// wheels on ice speed their robot up by mu g at most.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bullet_sim/simulation/world_api.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

constexpr double kSpeed = 1.5;  // [m/s] the crate's launch

/// A world of one ground plane whose surface has `mu`; `warnings`, when given, get the loader's.
WorldSpec floorWorld(double mu, std::vector<std::string>* warnings = nullptr) {
  const std::string sdf =
      "<sdf version='1.6'><world name='floor'><model name='ground_plane'><static>true</static>"
      "<link name='link'><collision name='collision'>"
      "<geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry>"
      "<surface><friction><ode><mu>" + std::to_string(mu) + "</mu><mu2>" + std::to_string(mu) +
      "</mu2></ode></friction></surface></collision></link></model></world></sdf>";
  return parseWorld(sdf, "floor.world", PackageResolver::fromEnvironment(), warnings);
}

/// A 0.4 m box link named `name` of 4 kg, with `mu` (none: Gazebo's default, 1).
std::string boxLink(const std::string& name, std::optional<double> mu) {
  const std::string box = "<geometry><box size=\"0.4 0.4 0.2\"/></geometry>";
  const std::string surface = mu ? "<gazebo reference=\"" + name + "\"><mu1>" + std::to_string(*mu) +
                                       "</mu1><mu2>" + std::to_string(*mu) + "</mu2></gazebo>"
                                 : "";
  return "<link name=\"" + name + "\"><inertial><mass value=\"4\"/>"
         "<inertia ixx=\"0.07\" iyy=\"0.07\" izz=\"0.1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
         "<collision>" + box + "</collision><visual>" + box + "</visual></link>" + surface;
}

/// How far the model `name`, resting on the floor, slides when sent along x at kSpeed; it stops within 3 s.
double slide(Simulation& simulation, const std::string& name) {
  WorldApi world(simulation);
  for (int i = 0; i < 200; ++i) simulation.step();  // settled
  EntityState launched = world.modelState(name);
  const double start = launched.pose.translation().x();
  launched.linear = Eigen::Vector3d(kSpeed, 0, 0);
  EXPECT_EQ(world.setModelState(name, launched), "");
  for (int i = 0; i < 3000; ++i) simulation.step();
  EXPECT_NEAR(world.modelState(name).linear.norm(), 0, 1e-3) << "it stopped";
  return world.modelState(name).pose.translation().x() - start;
}

double stoppingDistance(double mu, const WorldSpec& world) {
  return kSpeed * kSpeed / (2 * mu * world.gravity.norm());
}

struct Surfaces {
  double floor_mu;
  std::optional<double> crate_mu;
  double expected_mu;  // Gazebo's: the lesser
};

class Friction : public ::testing::TestWithParam<Surfaces> {};

TEST_P(Friction, ACrateSlidesAsTheLesserMuOfItsSurfaceAndTheFloorsSays) {
  const Surfaces& surfaces = GetParam();
  const WorldSpec world = floorWorld(surfaces.floor_mu);
  Simulation simulation(world);
  const std::string crate = "<robot name=\"crate\">" + boxLink("body", surfaces.crate_mu) + "</robot>";
  const bool warned = surfaces.crate_mu.value_or(1) < 0;  // a negative mu is taken with a warning
  simulation.spawn("crate",
                   warned ? parseModel(crate, "crate.urdf", PackageResolver::fromEnvironment(), nullptr)
                          : test::parseQuietly(crate, "crate.urdf"),
                   {.z = 0.1});
  const double expected = stoppingDistance(surfaces.expected_mu, world);
  EXPECT_NEAR(slide(simulation, "crate"), expected, 0.04 * expected);
}

INSTANTIATE_TEST_SUITE_P(
    Gazebo, Friction,
    ::testing::Values(Surfaces{0.2, std::nullopt, 0.2},  // an icy floor under a crate of the default mu
                      Surfaces{0.8, 0.5, 0.5},           // both below 1: the lesser, not their product
                      Surfaces{100, 0.5, 0.5},           // Gazebo's ground_plane (mu 100)
                      Surfaces{0.2, -1, 0.2},            // a negative mu is unlimited: the floor's decides
                      Surfaces{-1, 0.5, 0.5}));          // also a world's

// sdformat 12 refuses a negative <mu>; Gazebo's sdformat 9 reads it, and its FrictionPyramid::SetMu makes it
// unlimited.
TEST(NegativeMu, AWorldsNegativeMuLoadsAsUnlimitedWithAWarningNamingIt) {
  std::vector<std::string> warnings;
  const WorldSpec world = floorWorld(-1, &warnings);
  using ::testing::HasSubstr;
  EXPECT_THAT(warnings, ::testing::ElementsAre(
                            HasSubstr("[floor.world:1] <surface><friction><ode><mu> [-1.000000] is negative: "
                                      "read as unlimited friction, so the other surface's mu decides, as "
                                      "Gazebo reads it"),
                            HasSubstr("<mu2> [-1.000000] is negative")));
  ASSERT_EQ(world.models.size(), 1u);
  EXPECT_EQ(world.models.front().collisions.front().mu, SurfaceSpec::kUnlimitedMu);
}

// A sled's runner, fixed under its deck, is one body with it; the runner's mu meets the floor, not the
// deck's.
TEST(FrictionOfFixedLinks, EachCollisionTakesItsOwnLinksMu) {
  const WorldSpec world = floorWorld(1.0);
  Simulation simulation(world);
  const std::string sled = "<robot name=\"sled\">" + boxLink("deck", std::nullopt) + boxLink("runner", 0.1) +
                           "<joint name=\"fixed\" type=\"fixed\"><parent link=\"deck\"/>"
                           "<child link=\"runner\"/><origin xyz=\"0 0 -0.2\"/></joint></robot>";
  simulation.spawn("sled", test::parseQuietly(sled, "sled.urdf"), {.z = 0.3});
  const double expected = stoppingDistance(0.1, world);
  EXPECT_NEAR(slide(simulation, "sled"), expected, 0.04 * expected);
}

class WheelsOnIce : public ::testing::TestWithParam<std::string> {};

/// The two-wheeler's speed after 0.5 s of a 2 m/s command on a floor of `floor_mu` (its wheels' mu is 1).
double speedAfterHalfASecond(const std::string& wheel_model, double floor_mu) {
  Simulation simulation(floorWorld(floor_mu));
  const std::string urdf = test::twoWheelerWithDiffDrive({{"wheelTorque", "5"}, {"wheelModel", wheel_model}});
  Robot& robot = simulation.spawn("robot", test::parseQuietly(urdf, "two_wheeler.urdf"), {});
  WheeledDrive& drive = *test::pluginsOf<WheeledDrive>(robot).front();
  for (int i = 0; i < 200; ++i) simulation.step();  // settled
  test::stepSending(simulation, 0.5, [&] { return drive.setCommand(2.0, 0, simulation.time()); });
  return WorldApi(simulation).modelState("robot").linear.norm();
}

TEST_P(WheelsOnIce, TheFloorsLesserMuBoundsHowFastTheRobotSpeedsUp) {
  const double mu = 0.05;
  const double bound = mu * floorWorld(mu).gravity.norm() * 0.5;  // all its weight on its drive wheels
  const double on_ice = speedAfterHalfASecond(GetParam(), mu);
  EXPECT_GT(on_ice, 0.3 * bound) << "it moves";
  EXPECT_LT(on_ice, 1.05 * bound) << "no faster than Coulomb allows";
  EXPECT_GT(speedAfterHalfASecond(GetParam(), 1.0), 3 * bound) << "on a floor of mu 1, its motors decide";
}

INSTANTIATE_TEST_SUITE_P(BothWheelModels, WheelsOnIce, ::testing::Values("raycast", "contact"));

}  // namespace
}  // namespace bullet_sim
