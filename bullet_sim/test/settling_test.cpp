// How robots come to rest, as Gazebo's users expect: spawned under the ground they settle onto it instead of
// being catapulted; however heavy, they rest on their wheels; a robot whose root link is `world` is fixed to
// the world at its spawn pose; free wheels do not creep.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "bullet_sim/simulation/world_api.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

constexpr double kWheelRadius = 0.1;  // [m]

std::string inertial(double mass, double moment, const std::string& com = "0 0 0") {
  std::ostringstream text;
  text << "<inertial><origin xyz='" << com << "'/><mass value='" << mass << "'/><inertia ixx='" << moment
       << "' iyy='" << moment << "' izz='" << moment << "' ixy='0' ixz='0' iyz='0'/></inertial>";
  return text.str();
}

std::string wheel(const std::string& side, double y) {
  std::ostringstream text;
  text << "<link name='" << side << "_wheel'>" << inertial(0.5, 0.002)
       << "<collision><origin rpy='1.5707963267948966 0 0'/><geometry><cylinder radius='" << kWheelRadius
       << "' length='0.04'/></geometry></collision></link>"
       << "<joint name='" << side << "_wheel_joint' type='continuous'><parent link='base_link'/><child link='"
       << side << "_wheel'/><origin xyz='0.1 " << y << " 0'/><axis xyz='0 1 0'/></joint>";
  return text.str();
}

/// A two-wheeled robot with a caster ball, free wheels and no drive: base_link at the wheels' axle.
std::string freeWheeler() {
  return "<robot name='free'><link name='base_link'>" + inertial(10, 0.1) +
         "<collision><origin xyz='0 0 0.05'/><geometry><box size='0.4 0.3 0.1'/></geometry></collision>"
         "</link>" +
         wheel("left", 0.18) + wheel("right", -0.18) +
         "<link name='caster'>" + inertial(0.2, 0.0005) +
         "<collision><geometry><sphere radius='0.05'/></geometry></collision></link>"
         "<joint name='caster_joint' type='fixed'><parent link='base_link'/><child link='caster'/>"
         "<origin xyz='-0.15 0 -0.05'/></joint></robot>";
}

ModelSpec parse(const std::string& urdf) { return test::parseQuietly(urdf, "settling_test"); }

SpawnPose at(double x, double y, std::optional<double> z = std::nullopt) {
  SpawnPose pose;
  pose.x = x;
  pose.y = y;
  pose.z = z;
  return pose;
}

double speed(const WorldApi& world, const std::string& model) {
  const EntityState state = world.modelState(model);
  return state.linear.norm() + state.angular.norm();
}

// Husky's own launch file spawns at -z 0, its wheels under the ground. Bullet pushes a penetrating body out
// at erp * depth / dt: 80 m/s for 10 cm, which flew a robot 237 m. The push-out speed is capped.
TEST(Settling, ARobotSpawnedUnderTheGroundRestsOnItWhereItWasPut) {
  Simulation simulation(test::shippedWorld("empty.world"));
  WorldApi world(simulation);
  simulation.spawn("free", parse(freeWheeler()), at(1, 2, kWheelRadius - 0.1));
  double highest = -1;
  const bool rests = test::stepUntil(
      simulation,
      [&] {
        highest = std::max(highest, world.modelState("free").pose.translation().z());
        return simulation.time() > 0.5 && speed(world, "free") < 1e-3;
      },
      3.0, "coming to rest");
  ASSERT_TRUE(rests);
  const Eigen::Vector3d rest = world.modelState("free").pose.translation();
  EXPECT_NEAR(rest.z(), kWheelRadius, 0.01) << "on its wheels";
  EXPECT_LT((rest.head<2>() - Eigen::Vector2d(1, 2)).norm(), 0.3);
  EXPECT_LT(highest, kWheelRadius + 0.05) << "no jump out of the ground";
}

/// `urdf` without its plugins and sensors: nothing drives or holds its joints.
std::string withoutPlugins(const std::string& urdf) {
  return test::editUrdf(urdf, [](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      while (auto* plugin = gazebo->FirstChildElement("plugin")) gazebo->DeleteChild(plugin);
      while (auto* sensor = gazebo->FirstChildElement("sensor")) gazebo->DeleteChild(sensor);
    }
  });
}

/// How far [m] a robot moves in 10 s on flat ground once it has settled from its spawn.
double creep(const ModelSpec& model) {
  Simulation simulation(test::shippedWorld("empty.world"));
  WorldApi world(simulation);
  simulation.spawn("free", model, at(0, 0));
  for (int i = 0; i < 500; ++i) simulation.step();
  const Eigen::Vector3d settled = world.modelState("free").pose.translation();
  for (int i = 0; i < 10000; ++i) simulation.step();
  return (world.modelState("free").pose.translation() - settled).norm();
}

// A robot on free wheels is held by friction alone: four wheels on a plane share its weight in ways the
// solver must settle, and a solve that does not converge pushed the smartcar on at 2 mm/s^2.
// Clearpath's descriptions write every wheel's friction as attributes; sdformat reads them as the text form.
TEST(Settling, AttributeFormFrictionReadsAsTheTextForm) {
  const std::string urdf = test::replaceAfter(
      freeWheeler(), "</link>", "</robot>",
      "<gazebo reference='left_wheel'><mu1 value='0.3'/><mu2 value='0.4'/><kp value='1e6'/>"
      "<kd value='10'/></gazebo></robot>");
  const ModelSpec model = parse(urdf);  // no warning
  const SurfaceSpec& surface = model.link("left_wheel")->surface;
  EXPECT_DOUBLE_EQ(surface.mu1, 0.3);
  EXPECT_DOUBLE_EQ(surface.mu2, 0.4);
  EXPECT_DOUBLE_EQ(surface.kp.value_or(0), 1e6);
  EXPECT_DOUBLE_EQ(surface.kd.value_or(0), 10);
}

TEST(Settling, FreeWheelsDoNotCreep) {
  EXPECT_LT(creep(parse(freeWheeler())), 1e-3) << "two wheels and a caster ball";
  const std::string smartcar = test::expandXacro("smartcar_description", "urdf/smartcar.urdf.xacro");
  EXPECT_LT(creep(parse(withoutPlugins(smartcar))), 1e-3) << "the smartcar on four free wheels";
  const std::string chair =
      test::expandXacro("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro");
  EXPECT_LT(creep(parse(withoutPlugins(chair))), 1e-3) << "the wheelchair on free wheels and swivel casters";
}

// A robot rests on its wheels however heavy it is, up to our largest link mass: its contacts' compliance
// let a 1e4 kg base close on its caster at 0.3 m/s, faster than a contact's depth is corrected, and it
// sank 16 cm (contact model) or tipped back 40 degrees (raycast); 1e5 kg sank metres, on both.
TEST(Settling, AHeavyRobotRestsOnItsWheelsAsALightOneDoes) {
  for (const std::string& wheel_model : test::kWheelModels) {
    for (double step : {0.001, 0.01}) {
      std::optional<double> light_rest;
      for (double mass : {2.0, 1e4, 1e6}) {
        SCOPED_TRACE(wheel_model + ", " + std::to_string(step) + " s, a base of " + std::to_string(mass));
        ModelSpec model = test::parseQuietly(test::twoWheelerWithDiffDrive({{"wheelModel", wheel_model}}),
                                             "two_wheeler.urdf");
        for (LinkSpec& link : model.links) {
          if (link.name != "base_link") continue;
          link.inertial->inertia *= mass / link.inertial->mass;
          link.inertial->mass = mass;
        }
        SimulationOptions options;
        options.physics.step_size = step;
        Simulation simulation(test::shippedWorld("empty.world"), options);
        WorldApi world(simulation);
        simulation.spawn("robot", std::move(model), {});
        double lowest = 0, most_tilt = 0;
        while (simulation.time() < 2.0) {
          simulation.step();
          const Eigen::Isometry3d pose = world.modelState("robot").pose;
          lowest = std::min(lowest, pose.translation().z());
          most_tilt = std::max(most_tilt, std::acos(std::min(1.0, pose.linear()(2, 2))));
        }
        if (!light_rest) light_rest = world.modelState("robot").pose.translation().z();
        EXPECT_GT(lowest, *light_rest - 1e-3) << "sank";
        EXPECT_LT(most_tilt, 0.005) << "tipped";
      }
    }
  }
}

// A robot whose wheels and casters all touch the ground in its description rests level on level ground,
// however unequal their loads (the caster two-wheeler's centre of mass is 3 cm behind its axle).
TEST(Settling, ARobotRestsLevelOnWheelsOfUnequalLoad) {
  const std::string urdf = test::readFile(test::fixture("contact/caster_two_wheeler.urdf"));
  for (const std::string& wheel_model : test::kWheelModels) {
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("robot", parse(test::withWheelModel(urdf, wheel_model)), at(0, 0));
    for (int i = 0; i < 1000; ++i) simulation.step();
    const Eigen::Vector3d up = robot.body().linkPose("base_link").linear().col(2);
    EXPECT_LT(std::acos(std::min(1.0, up.z())), 3e-4) << wheel_model << ": tilt [rad] at rest";
  }
}

/// A two-link arm whose root link is `world`, as MoveIt's setups write it: world -> base (fixed) -> arm.
std::string armOnWorld(const std::string& base_joint) {
  return "<robot name='arm'><link name='world'/>"
         "<joint name='world_joint' type='" + base_joint + "'><parent link='world'/><child link='base'/>"
         "<origin xyz='0 0 0.5'/><axis xyz='0 0 1'/></joint>"
         "<link name='base'>" + inertial(2, 0.01) +
         "<collision><geometry><box size='0.1 0.1 0.1'/></geometry></collision></link>"
         "<joint name='shoulder' type='revolute'><parent link='base'/><child link='upper'/>"
         "<origin xyz='0 0 0.05'/><axis xyz='0 1 0'/><limit lower='-3' upper='3' effort='10' velocity='1'/>"
         "</joint><link name='upper'>" + inertial(1, 0.01, "0.2 0 0") +
         "<collision><origin xyz='0.2 0 0'/><geometry><box size='0.4 0.05 0.05'/></geometry></collision>"
         "</link></robot>";
}

TEST(Settling, ARootLinkNamedWorldIsFixedToTheWorldAtTheSpawnPose) {
  Simulation simulation(test::shippedWorld("empty.world"));
  SpawnPose pose = at(1, -1);
  pose.yaw = M_PI / 2;
  simulation.spawn("arm", parse(armOnWorld("fixed")), pose);
  const RobotBody& body = simulation.robot("arm")->body();
  double swing = 0;  // [rad] the most the shoulder turned
  for (int i = 0; i < 2000; ++i) {
    simulation.step();
    swing = std::max(swing, std::abs(body.jointPosition(body.jointIndex("shoulder"))));
  }
  const Eigen::Isometry3d base = body.linkPose("base");
  EXPECT_TRUE(base.translation().isApprox(Eigen::Vector3d(1, -1, 0.5), 1e-6))
      << base.translation().transpose();
  EXPECT_NEAR(base.linear()(1, 0), 1.0, 1e-6) << "turned by the spawn yaw";
  // The arm swings down under gravity about its shoulder, which stays put.
  EXPECT_GT(swing, M_PI / 2);
}

TEST(Settling, AMovingJointToTheWorldTurnsItsChildAgainstTheWorld) {
  Simulation simulation(test::shippedWorld("empty.world"));
  simulation.spawn("arm", parse(armOnWorld("continuous")), at(0, 0));
  RobotBody& body = simulation.robot("arm")->body();
  body.setJointVelocity(body.jointIndex("world_joint"), 1.0, 100);
  for (int i = 0; i < 1000; ++i) simulation.step();
  EXPECT_NEAR(body.jointPosition(body.jointIndex("world_joint")), 1.0, 0.05);
  EXPECT_TRUE(body.linkPose("base").translation().isApprox(Eigen::Vector3d(0, 0, 0.5), 1e-6));
}

}  // namespace
}  // namespace bullet_sim
