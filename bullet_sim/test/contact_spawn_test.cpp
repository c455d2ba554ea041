// Issue 28: robots spawned under the ground rise onto it without a leap and come to rest, with or without a
// drive, on both wheel models at 1 and 10 ms; where a world's step is too coarse for a robot's stiffest
// spring or lightest link, physics substeps while time, plugins and sensors keep the world's step; and a
// robot set down onto the ground at up to 50 m/s lands level.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bullet_sim/simulation/world_api.h"
#include "contact_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

/// `urdf` without its plugins and sensors: nothing drives it, and it gets the contact wheel model.
std::string withoutPlugins(const std::string& urdf) {
  return test::editUrdf(urdf, [](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      while (auto* plugin = gazebo->FirstChildElement("plugin")) gazebo->DeleteChild(plugin);
      while (auto* sensor = gazebo->FirstChildElement("sensor")) gazebo->DeleteChild(sensor);
    }
  });
}

/// [m] the smallest wheel radius: continuous joints whose link collides as a cylinder or a sphere.
double smallestWheel(const ModelSpec& model) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const auto& joint : model.joints) {
    const LinkSpec* link = model.link(joint.child);
    if (joint.type != JointSpec::Type::kContinuous || !link || link->collisions.empty()) continue;
    const Shape& shape = link->collisions.front().shape;
    if (shape.type == Shape::Type::kCylinder || shape.type == Shape::Type::kSphere)
      smallest = std::min(smallest, shape.radius);
  }
  return smallest;
}

SimulationOptions stepOf(double step) {
  SimulationOptions options;
  options.physics.step_size = step;
  return options;
}

/// Spawns `model` as deep under the ground as issue 28 asks (10 cm, or its smallest wheel's radius when less)
/// and checks that it rises without a leap (its peak at most 5 cm above where it rests) and rests (below
/// 1 cm/s and 0.02 rad/s for 0.5 s) within 3 s.
void expectRisesAndRests(const ModelSpec& model, double step) {
  Simulation simulation(test::emptyWorld(), stepOf(step));
  WorldApi world(simulation);
  simulation.spawn("robot", model, {});
  const double depth = std::min(0.1, smallestWheel(model));
  EntityState buried = world.modelState("robot");
  buried.pose.translation().z() -= depth;
  world.setModelState("robot", buried);
  double peak = -1, still_since = 0;
  bool resting = false;
  while (simulation.time() < 6.0 && !resting) {
    simulation.step();
    const EntityState state = world.modelState("robot");
    peak = std::max(peak, state.pose.translation().z());
    if (state.linear.norm() >= 0.01 || state.angular.norm() >= 0.02) still_since = simulation.time();
    resting = simulation.time() - still_since >= 0.5;
  }
  EXPECT_TRUE(resting) << "still moving after 6 s";
  EXPECT_LE(still_since, 3.0) << "came to rest at " << still_since << " s";
  const double rest = world.modelState("robot").pose.translation().z();
  EXPECT_LE(peak, rest + 0.05) << "buried " << depth << " m, rests at " << rest << " m";
  EXPECT_GT(rest, buried.pose.translation().z() + depth - 0.01) << "back on the ground";
}

TEST(SpawnedUnderTheGround, ARobotWithADriveRisesWithoutALeap) {
  for (const StrikeRobot& robot : test::lookAlikes()) {
    for (const std::string& model : test::kWheelModels) {
      for (double step : {0.001, 0.01}) {
        SCOPED_TRACE(robot.name + " " + model + " " + std::to_string(step) + " s");
        expectRisesAndRests(test::modelOf(robot, model), step);
      }
    }
  }
}

TEST(SpawnedUnderTheGround, AShippedRobotRisesWithoutALeapWithItsDriveOrWithout) {
  const auto shipped = test::shippedRobots();
  for (size_t r = 0; r < 4; ++r) {  // the rover drives through ros_control, which needs its parameters
    const StrikeRobot& robot = shipped[r];
    for (double step : {0.001, 0.01}) {
      for (const std::string& model : test::kWheelModels) {
        SCOPED_TRACE(robot.name + " " + model + " " + std::to_string(step) + " s");
        expectRisesAndRests(test::modelOf(robot, model), step);
      }
      SCOPED_TRACE(robot.name + " without its plugins, " + std::to_string(step) + " s");
      expectRisesAndRests(test::parseQuietly(withoutPlugins(robot.urdf), robot.name), step);
    }
  }
}

// The raycast suspension (0.5 mm of sag: 140 rad/s) wants substeps of at most 1 / (5 x 140 rad/s) = 1.43 ms.
TEST(Substeps, ATenMillisecondWorldSubstepsForTheStiffestSpringAndTimeKeepsTheWorldsStep) {
  Simulation simulation(test::emptyWorld(), stepOf(0.01));
  simulation.spawn("robot", test::modelOf(test::lookAlike("light_skid_steer"), "raycast"), {});
  EXPECT_THAT(simulation.substepNote("robot"), HasSubstr("physics substep 1.25 ms (8 per 10 ms step)"));
  EXPECT_THAT(simulation.substepNote("robot"),
              HasSubstr("the raycast suspension's 140 rad/s allows 1.43 ms"));
  simulation.step();
  EXPECT_DOUBLE_EQ(simulation.time(), 0.01);

  Simulation fine(test::emptyWorld(), stepOf(0.001));
  fine.spawn("robot", test::modelOf(test::lookAlike("light_skid_steer"), "raycast"), {});
  EXPECT_THAT(fine.substepNote("robot"), HasSubstr("physics substep 1 ms (1 per 1 ms step)"));
}

// The springs keep the stiffness they were spawned with: a later change of gravity (set_physics_properties)
// leaves the substep they need as it was.
TEST(Substeps, TheSuspensionsSubstepOutlivesAChangeOfGravity) {
  Simulation simulation(test::emptyWorld(), stepOf(0.001));
  WorldApi world(simulation);
  simulation.spawn("robot", test::modelOf(test::lookAlike("light_skid_steer"), "raycast"), {});
  world.setPhysicsProperties({0.001, 1000, Eigen::Vector3d(0, 0, -1.62)});
  world.setPhysicsProperties({0.01, 1000, Eigen::Vector3d(0, 0, -1.62)});
  EXPECT_THAT(simulation.substepNote("robot"), HasSubstr("physics substep 1.25 ms (8 per 10 ms step)"));
  EXPECT_THAT(simulation.substepNote("robot"),
              HasSubstr("the raycast suspension's 140 rad/s allows 1.43 ms"));
}

// Gazebo takes a weightless world. A robot put down on the ground in one floats off no faster than its
// compressed springs push it (their energy, 1/2 m g_sized x, gives at most sqrt(g x) = 7 cm/s), without
// turning, and its state stays finite.
TEST(WeightlessWorld, ARobotFloatsOffTheGroundGentlyAndStaysWhole) {
  std::vector<std::pair<std::string, ModelSpec>> robots;
  for (const std::string& model : test::kWheelModels) {
    robots.emplace_back("wheelchair " + model, test::wheelchair(model));
    for (const StrikeRobot& robot : test::lookAlikes())
      robots.emplace_back(robot.name + " " + model, test::modelOf(robot, model));
  }
  WorldSpec weightless = test::emptyWorld();
  weightless.gravity.setZero();
  for (const auto& [name, spec] : robots) {
    for (double step : {0.001, 0.01}) {
      SCOPED_TRACE(name + " " + std::to_string(step) + " s");
      Simulation simulation(weightless, stepOf(step));
      WorldApi world(simulation);
      simulation.spawn("robot", spec, {});
      while (simulation.time() < 2.0) {
        simulation.step();
        const EntityState state = world.modelState("robot");
        ASSERT_TRUE(state.pose.matrix().allFinite()) << "at " << simulation.time() << " s";
        ASSERT_LT(state.linear.norm(), 0.08) << "at " << simulation.time() << " s";
        ASSERT_LT(state.angular.norm(), 0.01) << "at " << simulation.time() << " s";
      }
    }
  }
}

// A damping far beyond what the substeps can follow (1e6 N m s/rad on a 10 g caster's swivel wants substeps
// of 1e-13 s; physics cuts a step into at most a thousand) holds the joint still instead of reversing it
// ever faster: the robot stays where it was put, upright. The spawn says the robot runs slowly.
TEST(Substeps, AJointDampedBeyondWhatSubstepsFollowIsHeldStillAndTheSpawnSaysSo) {
  ModelSpec spec = test::modelOf(test::lookAlike("caster_two_wheeler"), "contact");
  for (JointSpec& joint : spec.joints) {
    if (joint.name.find("swivel") != std::string::npos) joint.damping = 1e6;
  }
  Simulation simulation(test::emptyWorld(), stepOf(0.01));
  WorldApi world(simulation);
  std::vector<std::string> warnings;
  simulation.spawn("robot", spec, {}, &warnings);
  std::string said;
  for (const auto& warning : warnings) said += warning + "\n";
  EXPECT_THAT(said, HasSubstr("robot [robot]: joint [front_swivel_joint]'s damping of 1e+06"));
  EXPECT_THAT(said, HasSubstr("physics cuts a step into at most 1000 (0.01 ms)"));
  const Eigen::Vector3d start = world.modelState("robot").pose.translation();
  while (simulation.time() < 0.5) simulation.step();
  const EntityState state = world.modelState("robot");
  EXPECT_LT((state.pose.translation() - start).norm(), 0.01);
  EXPECT_GT(state.pose.linear()(2, 2), std::cos(0.02)) << "tilted";
}

// Joint damping acts explicitly, so the Yahboom car's pan/tilt (0.001 N m s/rad on a few g cm^2) sets the
// contact model's substep; on the caster look-alike, its 10 g casters under 1.1 kg do:
// 20 ms * sqrt(0.01 / 1.1) = 1.9 ms. Neither limits a 1 ms world.
TEST(Substeps, TheLightestLinkSetsTheContactModelsSubstep) {
  Simulation simulation(test::emptyWorld(), stepOf(0.01));
  simulation.spawn("yahboom", test::modelOf(test::shippedRobots()[2], "contact"), {});
  EXPECT_THAT(simulation.substepNote("yahboom"), HasSubstr("joint [jq"));
  EXPECT_THAT(simulation.substepNote("yahboom"), HasSubstr("(4 per 10 ms step)"));

  Simulation casters(test::emptyWorld(), stepOf(0.01));
  casters.spawn("robot", test::modelOf(test::lookAlike("caster_two_wheeler"), "contact"), {});
  EXPECT_THAT(casters.substepNote("robot"), HasSubstr("(6 per 10 ms step)"));
  EXPECT_THAT(casters.substepNote("robot"),
              HasSubstr("caster] of 0.01 kg on a robot of 1.1 kg allows 1.91 ms"));

  Simulation fine(test::emptyWorld(), stepOf(0.001));
  fine.spawn("robot", test::modelOf(test::lookAlike("caster_two_wheeler"), "contact"), {});
  EXPECT_THAT(fine.substepNote("robot"), HasSubstr("(1 per 1 ms step)"));
}

/// [m/s] the robot's centre of mass's velocity.
Eigen::Vector3d centreOfMassVelocity(const RobotBody& body) {
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  double mass = 0;
  for (const auto& link : body.spec().links) {
    if (!link.inertial) continue;
    const Eigen::Isometry3d pose = body.linkPose(link.name);
    const Eigen::Vector3d offset = pose.linear() * link.inertial->com;
    momentum += link.inertial->mass *
                (body.linkLinearVelocity(link.name) + body.linkAngularVelocity(link.name).cross(offset));
    mass += link.inertial->mass;
  }
  return momentum / mass;
}

// Bullet forgets forces after each of its steps: a wrench given for one world step must act through all its
// substeps. A 1 N push for one 10 ms step on a weightless robot changes its speed by 0.01 / M m/s.
TEST(Substeps, AWrenchActsThroughEverySubstepOfItsStep) {
  for (const std::string& model : test::kWheelModels) {
    SCOPED_TRACE(model);
    WorldSpec weightless = test::emptyWorld();
    weightless.gravity.setZero();
    Simulation simulation(weightless, stepOf(0.01));
    const ModelSpec spec = test::modelOf(test::lookAlike("light_skid_steer"), model);
    const double mass = robotMass(spec);
    Robot& robot = simulation.spawn("robot", spec, {.x = 0, .y = 0, .yaw = 0, .z = 1.0});
    robot.body().applyLinkWrench("base_link", Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero());
    simulation.step();
    EXPECT_NEAR(centreOfMassVelocity(robot.body()).x(), 0.01 / mass, 1e-3 * 0.01 / mass);
  }
}

/// [rad] how far `pose` tilts from level: the angle between its z axis and the world's.
double tiltOf(const Eigen::Isometry3d& pose) {
  return std::acos(std::clamp(pose.linear()(2, 2), -1.0, 1.0));
}

// A robot set onto flat ground moving straight down (the world API's set_model_state with a twist) lands as
// a rigid body on rigid ground would: level, where it rests, without a leap. Bullet's contact compliance let
// the wheelchair's front rims through at 4.5 m/s and its rear ones at 1.6 m/s in a 50 m/s strike: it left
// pitching at 4.8 rad/s, pivoted over its drive wheels and ended on its back (raycast wheels).
TEST(SetDownHard, TheWheelchairSlammedOntoFlatGroundLandsLevel) {
  for (const std::string& model : test::kWheelModels) {
    for (double speed : {3.0, 10.0, 50.0}) {
      SCOPED_TRACE(model + " at " + std::to_string(speed) + " m/s");
      Simulation simulation(test::shippedWorld("empty.world"));
      WorldApi world(simulation);
      simulation.spawn("wheelchair", test::wheelchair(model), {});
      for (int i = 0; i < 1000; ++i) simulation.step();
      const double rest = world.modelState("wheelchair").pose.translation().z();
      EntityState slam;
      slam.pose.translation() = Eigen::Vector3d(0, -0.9, 0);
      slam.linear = Eigen::Vector3d(0, 0, -speed);
      ASSERT_EQ(world.setModelState("wheelchair", slam), "");
      double most_tilt = 0, peak = -1;
      const double start = simulation.time();
      while (simulation.time() - start < 3.0) {
        simulation.step();
        const EntityState now = world.modelState("wheelchair");
        most_tilt = std::max(most_tilt, tiltOf(now.pose));
        peak = std::max(peak, now.pose.translation().z());
      }
      const EntityState end = world.modelState("wheelchair");
      EXPECT_LT(most_tilt, 0.1) << "tilted on landing";
      EXPECT_LT(tiltOf(end.pose), 0.005) << "rests level";
      EXPECT_NEAR(end.pose.translation().z(), rest, 0.01) << "on its wheels, where it rested before";
      EXPECT_LT(peak, rest + 0.05) << "no leap";
      EXPECT_LT(Eigen::Vector2d(end.pose.translation().x(), end.pose.translation().y() + 0.9).norm(), 0.1)
          << "lands where it was set down";
      EXPECT_LT(end.linear.norm(), 0.01);
      EXPECT_LT(end.angular.norm(), 0.02);
    }
  }
}

}  // namespace
}  // namespace bullet_sim
