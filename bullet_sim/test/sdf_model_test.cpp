// SDF models to spawn (spawn_sdf_model): read with libsdformat into the ModelSpec a URDF gives (links,
// inertia, collisions, visuals, joints, sensors and plugins through the registry), simulated as URDF robots
// are, and the problems SDF can have that a URDF cannot.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/gazebo_names.h"
#include "bullet_sim/model/sdf_model.h"
#include "plugins/ray_lidar/ray_lidar.h"
#include "bullet_sim/plugins/registry.h"
#include "bullet_sim/simulation/world_api.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

/// A box on the ground with a lidar head on a pan joint 0.6 m up: two links, a revolute joint and a sensor.
std::string panLidar() { return test::readFile(test::fixture("models/pan_lidar.sdf")); }

ModelSpec parse(const std::string& sdf, std::vector<std::string>* warnings = nullptr) {
  return parseSdfModel(sdf, "test.sdf", PackageResolver::fromEnvironment(), PluginRegistry::builtin(),
                       warnings);
}

/// The SpecError message of parsing `sdf`, or "" when it parses.
std::string parseError(const std::string& sdf) {
  try {
    parse(sdf);
  } catch (const SpecError& error) {
    return error.what();
  }
  return "";
}

/// A model of `body` (links and joints) in an <sdf>.
std::string model(const std::string& body, bool is_static = false) {
  return std::string("<sdf version=\"1.6\"><model name=\"m\">") + (is_static ? "<static>true</static>" : "") +
         body + "</model></sdf>";
}

std::string link(const std::string& name, const std::string& pose = "0 0 0 0 0 0", bool massless = false) {
  return "<link name=\"" + name + "\"><pose>" + pose + "</pose>" +
         (massless
              ? "<inertial><mass>0</mass><inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial>"
              : "") +
         "<collision name=\"c\"><geometry><box><size>0.2 0.2 0.2</size></box></geometry></collision></link>";
}

TEST(SdfModel, ReadsLinksInertiaShapesJointsAndTheSensorsPluginAsAUrdfWouldGiveThem) {
  std::vector<std::string> warnings;
  const ModelSpec spec = parse(panLidar(), &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(spec.name, "pan_lidar");
  EXPECT_EQ(spec.root, "base");
  EXPECT_TRUE(spec.root_in_model.translation().isApprox(Eigen::Vector3d(0, 0, 0.1)));
  EXPECT_THAT(spec.linkNames(), ElementsAre("base", "head"));
  const LinkSpec& head = *spec.link("head");
  ASSERT_TRUE(head.inertial);
  EXPECT_DOUBLE_EQ(head.inertial->mass, 0.2);
  EXPECT_TRUE(head.inertial->com.isApprox(Eigen::Vector3d(0.01, 0, 0)));
  EXPECT_DOUBLE_EQ(head.inertial->inertia(2, 2), 2e-4);
  ASSERT_EQ(head.collisions.size(), 1u);
  EXPECT_EQ(head.collisions[0].shape.type, Shape::Type::kCylinder);
  EXPECT_DOUBLE_EQ(head.surface.mu1, 0.4);
  EXPECT_DOUBLE_EQ(head.surface.mu2, 0.3);
  ASSERT_EQ(spec.link("base")->visuals.size(), 1u);
  EXPECT_TRUE(spec.link("base")->visuals[0].rgba.isApprox(Eigen::Vector4d(1, 0, 0, 1)));
  const JointSpec& pan = *spec.joint("pan");
  EXPECT_EQ(pan.type, JointSpec::Type::kRevolute);
  EXPECT_EQ(pan.parent, "base");
  EXPECT_TRUE(pan.origin.translation().isApprox(Eigen::Vector3d(0, 0, 0.5)))
      << "the head in the base's frame";
  EXPECT_TRUE(pan.axis.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_DOUBLE_EQ(pan.lower, -3);
  EXPECT_DOUBLE_EQ(pan.upper, 3);
  EXPECT_DOUBLE_EQ(pan.effort, 1);
  EXPECT_DOUBLE_EQ(pan.damping, 0.1);
  ASSERT_EQ(spec.plugins.size(), 1u);
  const PluginDeclaration& lidar = spec.plugins[0];
  ASSERT_TRUE(lidar.sensor);
  EXPECT_EQ(lidar.sensor->link, "head");
  EXPECT_EQ(lidar.sensor->type, "ray");
  EXPECT_DOUBLE_EQ(lidar.sensor->update_rate, 10);
  EXPECT_TRUE(lidar.sensor->pose.translation().isApprox(Eigen::Vector3d(0.02, 0, 0)));
  const auto* config = lidar.configAs<RayLidarConfig>();
  ASSERT_NE(config, nullptr);
  EXPECT_EQ(config->topic, "scan");
}

TEST(SdfModel, ASensorsNegativeUpdateRateIsEveryStepWithAWarningAsInAUrdf) {
  std::vector<std::string> warnings;
  const ModelSpec spec =
      parse(test::replaceAfter(panLidar(), "<sensor", "<update_rate>10<", "<update_rate>-1<"), &warnings);
  EXPECT_THAT(warnings, ElementsAre(HasSubstr("sensor [lidar] <update_rate> -1 is below 0: read as 0, every "
                                              "step, as Gazebo does")));
  ASSERT_EQ(spec.plugins.size(), 1u);
  EXPECT_EQ(spec.plugins[0].sensor->update_rate, 0.0);
  EXPECT_EQ(spec.plugins[0].configAs<RayLidarConfig>()->update_rate, 0.0);
}

TEST(SdfModel, ANegativeMuIsUnlimitedWithAWarningAsGazeboReadsIt) {
  std::vector<std::string> warnings;
  const std::string head = "<collision name=\"head\">";
  const ModelSpec spec = parse(test::replaceAfter(panLidar(), head, "<mu>0.4<", "<mu>-1<"), &warnings);
  EXPECT_THAT(warnings,
              ElementsAre(HasSubstr("[test.sdf:23] <surface><friction><ode><mu> [-1] is negative: read as "
                                    "unlimited friction, so the other surface's mu decides")));
  EXPECT_EQ(spec.link("head")->surface.mu1, SurfaceSpec::kUnlimitedMu);
  EXPECT_EQ(spec.link("head")->surface.mu2, 0.3);
}

TEST(SdfModel, AnAxisOfTinyLengthIsItsDirectionAsGazebosOdeTakesIt) {
  std::vector<std::string> warnings;
  const ModelSpec spec = parse(test::replaceAfter(panLidar(), "<axis>", "<xyz>0 0 1<", "<xyz>0 0 1e-12<"),
                               &warnings);
  EXPECT_THAT(warnings,
              ElementsAre(HasSubstr("[test.sdf:43] joint [pan] <axis><xyz> [0 0 1e-12] is 1e-12 long, which "
                                    "sdformat 12 calls zero: read as its direction, 0 0 1, as Gazebo's ODE "
                                    "normalizes it")));
  EXPECT_EQ(spec.joint("pan")->axis, Eigen::Vector3d::UnitZ());
}

TEST(SdfModel, ASpawnedSdfModelScansTheRoomAndItsJointTurnsTheHead) {
  Simulation simulation(test::shippedWorld("test_room.world"));
  WorldApi world(simulation);
  Robot& robot = simulation.spawn("pan_lidar", parse(panLidar()), {.z = 0.1});  // the root link, 0.1 m up
  EXPECT_TRUE(world.modelState("pan_lidar").pose.translation().isApprox(Eigen::Vector3d::Zero(), 1e-9))
      << "the model frame is 0.1 m below its root link";
  const Stream<LaserScan>& lidar = *robot.outputs<LaserScan>().at(0).stream;
  const auto ahead = [&] {
    const uint64_t scans = lidar.count();
    test::stepUntil(
        simulation, [&] { return lidar.count() > scans; }, 1.0, "a scan");
    return lidar.latest().ranges[90];
  };
  // The test room's inner faces are at x = 3 and y = 2; the sensor sits 0.02 m ahead of the pan axis.
  EXPECT_NEAR(ahead(), 3.0 - 0.02, 1e-3);
  world.setModelConfiguration("pan_lidar", {{"pan", M_PI / 2}});
  EXPECT_NEAR(ahead(), 2.0 - 0.02, 1e-3) << "the head turned to +y";
}

TEST(SdfModel, AStaticModelIsRigidNeedsNoMassAndStaysWhereItIsPut) {
  const ModelSpec spec = parse(model(link("a", "0 0 0 0 0 0", true) + link("b", "1 0 0 0 0 0", true), true));
  EXPECT_TRUE(spec.is_static);
  EXPECT_THAT(spec.linkNames(), ElementsAre("a", "b")) << "the unjoined link is welded to the root";
  Simulation simulation(test::shippedWorld("empty.world"));
  WorldApi world(simulation);
  simulation.spawn("goal", spec, {.x = 2, .z = 0.5});
  for (int i = 0; i < 500; ++i) simulation.step();
  EXPECT_TRUE(world.modelState("goal").pose.translation().isApprox(Eigen::Vector3d(2, 0, 0.5), 1e-9));
  EXPECT_TRUE(world.modelProperties("goal").is_static);
  EntityState moved;
  moved.pose.translation() = Eigen::Vector3d(-1, 1, 0.5);
  EXPECT_EQ(world.setModelState("goal", moved), "");
  for (int i = 0; i < 100; ++i) simulation.step();
  EXPECT_TRUE(world.linkState("goal::b").pose.translation().isApprox(Eigen::Vector3d(0, 1, 0.5), 1e-9));
  EXPECT_THAT(
      [&] {
        world.applyBodyWrench({"goal", "", {}, Eigen::Vector3d::UnitX(), {}, {0, 1}});
      },
      ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("static")));
}

TEST(SdfModel, AUrdfSaysStaticInAGazeboBlock) {
  const std::string urdf = test::replaceAfter(test::readFile(test::fixture("robots/minimal.urdf")), "</link>",
                                              "</robot>", "<gazebo><static>true</static></gazebo></robot>");
  Simulation simulation(test::shippedWorld("empty.world"));
  WorldApi world(simulation);
  simulation.spawn("box", test::parseQuietly(urdf, "minimal.urdf"), {.z = 1});
  for (int i = 0; i < 300; ++i) simulation.step();
  EXPECT_NEAR(world.modelState("box").pose.translation().z(), 1.0, 1e-9);
  EXPECT_TRUE(world.modelProperties("box").is_static);
}

TEST(SdfModel, AJointAwayFromItsChildsOriginPutsTheChildsFrameAtTheJoint) {
  std::vector<std::string> warnings;
  const ModelSpec spec = parse(model(link("a") + link("b", "0 0 1 0 0 0") +
                                     R"(<joint name="j" type="revolute"><pose>0.5 0 0 0 0 0</pose>
                                          <parent>a</parent><child>b</child>
                                          <axis><xyz>0 1 0</xyz></axis></joint>)"),
                               &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0],
              HasSubstr("joint [j] turns link [b] about a point [0.5 0 0] m from the link's origin"));
  EXPECT_TRUE(spec.joint("j")->origin.translation().isApprox(Eigen::Vector3d(0.5, 0, 1)));
  EXPECT_TRUE(spec.link("b")->collisions[0].origin.translation().isApprox(Eigen::Vector3d(-0.5, 0, 0)));
}

TEST(SdfModel, WhatAUrdfCannotSayIsRefusedWithTheReason) {
  EXPECT_THAT(parseError(model(link("a") + link("b"))),
              HasSubstr("links [a], [b] of model [m] are joined to nothing"));
  EXPECT_THAT(parseError(model(link("a") + link("b") + R"(<joint name="ball" type="ball"><parent>a</parent>
                                   <child>b</child></joint>)")),
              HasSubstr("joint [ball]: type [ball] is not supported"));
  EXPECT_THAT(parseError("<sdf version=\"1.6\"><world name=\"w\"/></sdf>"), HasSubstr("no <model> element"));
}

TEST(SdfModel, JointsToTheWorldHangTheModelFromALinkNamedWorld) {
  const ModelSpec fixed = parse(model(link("a") + R"(<joint name="bolt" type="fixed"><parent>world</parent>
                                        <child>a</child></joint>)"));
  EXPECT_EQ(fixed.root, "world");
  EXPECT_TRUE(hasFixedBase(fixed)) << "a model fixed to the world never moves";
  EXPECT_FALSE(fixed.is_static) << "but it is not <static>: its other joints move";
  const ModelSpec hinged =
      parse(model(link("a") + R"(<joint name="hinge" type="revolute"><parent>world</parent>
                                   <child>a</child><axis><xyz>0 0 1</xyz></axis></joint>)"));
  EXPECT_EQ(hinged.root, "world");
  ASSERT_NE(hinged.joint("hinge"), nullptr);
  EXPECT_TRUE(hinged.joint("hinge")->moves());
  EXPECT_EQ(hinged.joint("hinge")->parent, "world");
}

TEST(SdfModel, LinksAndCollisionsKeepTheirSdfNamesAsGazeboKeepsThem) {
  const ModelSpec spec =
      parse(model(link("a") + link("b", "0 0 1 0 0 0") +
                  R"(<joint name="weld" type="fixed"><parent>a</parent><child>b</child></joint>)"));
  std::vector<std::string> names;
  for (const GazeboCollision& collision : gazeboCollisions(spec))
    names.push_back(collision.gazebo_link + "::" + collision.name);
  EXPECT_THAT(names, ElementsAre("a::c", "b::c")) << "no lumping, no _collision suffix";
}

}  // namespace
}  // namespace bullet_sim
