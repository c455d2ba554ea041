// Bodies at rest sleep as Gazebo's do (ODE's auto-disable: 1 s under 0.1 m/s and 0.1 rad/s; only models
// without joints, sensors or plugins, and not when <allow_auto_disable> is false), and whatever reaches a
// sleeper wakes it: a wrench, a teleport, a contact, the body under it removed or moved, gravity changed;
// what does not reach it (a body removed far away) leaves it asleep. Before it sleeps, a body at rest costs
// the solver one iteration a step.
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <gtest/gtest.h>

#include "bullet_sim/simulation/world_api.h"
#include "contact_support.h"

namespace bullet_sim {
namespace {

constexpr double kGravity = 9.81;
constexpr double kSide = 0.4;  // [m] every crate is a 0.4 m cube of 4 kg
constexpr double kMass = 4;

/// A 0.4 m cube of 4 kg, one link and nothing else: a body Gazebo lets sleep.
ModelSpec crate() {
  const std::string box = "<geometry><box size=\"0.4 0.4 0.4\"/></geometry>";
  return test::parseQuietly(
      "<robot name=\"crate\"><link name=\"body\"><inertial><mass value=\"4\"/>"
      "<inertia ixx=\"0.107\" iyy=\"0.107\" izz=\"0.107\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
      "<collision>" + box + "</collision><visual>" + box + "</visual></link></robot>",
      "crate.urdf");
}

/// A crate named `name` with its centre at (x, 0, z).
void spawnCrate(Simulation& simulation, const std::string& name, double x, double z) {
  simulation.spawn(name, crate(), {.x = x, .z = z});
}

bool sleeping(const Simulation& simulation, const std::string& model) {
  return simulation.robot(model)->body().sleeping();
}

double heightOf(const WorldApi& world, const std::string& model) {
  return world.modelState(model).pose.translation().z();
}

void stepFor(Simulation& simulation, double seconds) {
  const double end = simulation.time() + seconds;
  while (simulation.time() < end - 1e-9) simulation.step();
}

/// Steps until every one of `crates` sleeps (at most 3 s).
void settle(Simulation& simulation, const std::vector<std::string>& crates) {
  const auto asleep = [&] {
    return std::all_of(crates.begin(), crates.end(),
                       [&](const std::string& name) { return sleeping(simulation, name); });
  };
  ASSERT_TRUE(test::stepUntil(simulation, asleep, 3.0, "every crate asleep"));
}

/// Crate "top" asleep on crate "bottom", asleep on the ground.
void stackTwoCrates(Simulation& simulation) {
  spawnCrate(simulation, "bottom", 0, kSide / 2);
  spawnCrate(simulation, "top", 0, 1.5 * kSide);
  settle(simulation, {"bottom", "top"});
}

TEST(Sleeping, ACrateAtRestSleepsAfterOneSecondAndStaysWhereItWas) {
  Simulation simulation(test::emptyWorld());
  WorldApi world(simulation);
  spawnCrate(simulation, "crate", 0, kSide / 2);
  stepFor(simulation, 0.9);
  EXPECT_FALSE(sleeping(simulation, "crate")) << "Gazebo waits 1 s at rest";
  stepFor(simulation, 0.3);
  EXPECT_TRUE(sleeping(simulation, "crate"));
  EXPECT_NEAR(heightOf(world, "crate"), kSide / 2, 1e-3);
}

/// The normal impulses [N s] the crate took from the ground in the last step's solve.
double groundImpulse(Simulation& simulation) {
  btDispatcher& dispatcher = *simulation.physics().bullet().getDispatcher();
  double impulse = 0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
    for (int p = 0; p < manifold.getNumContacts(); ++p)
      impulse += manifold.getContactPoint(p).m_appliedImpulse;
  }
  return impulse;
}

TEST(Sleeping, ACrateAtRestCostsTheSolverOneIterationAStepUntilItSleeps) {
  Simulation simulation(test::emptyWorld());
  spawnCrate(simulation, "crate", 0, kSide / 2);
  stepFor(simulation, 0.3);  // settled: it was spawned touching the ground
  const auto& solver = dynamic_cast<const btSequentialImpulseConstraintSolver&>(
      *simulation.physics().bullet().getConstraintSolver());
  while (simulation.time() < 0.9) {  // Gazebo waits 1 s at rest
    simulation.step();
    SCOPED_TRACE(simulation.time());
    ASSERT_FALSE(sleeping(simulation, "crate"));
    // Started from the last step's impulses, in full, the solve finds them unchanged at once: the ground
    // carries the crate's weight over the step.
    ASSERT_EQ(solver.m_analyticsData.m_numIterationsUsed, 1);
    ASSERT_NEAR(groundImpulse(simulation), kMass * kGravity * simulation.stepSize(), 1e-6);
  }
}

TEST(Sleeping, AWrenchWakesASleeperAndMovesItByNewtonsLaw) {
  Simulation simulation(test::emptyWorld());
  WorldApi world(simulation);
  spawnCrate(simulation, "crate", 0, kSide / 2);
  settle(simulation, {"crate"});
  const double force = 80, rest = heightOf(world, "crate"), seconds = 0.3;
  BodyWrench lift;
  lift.body = "crate::body";
  lift.force = Eigen::Vector3d(0, 0, force);
  lift.schedule.duration = seconds;
  ASSERT_EQ(world.applyBodyWrench(lift), "");
  stepFor(simulation, seconds);
  const double acceleration = force / kMass - kGravity;
  EXPECT_NEAR(heightOf(world, "crate") - rest, acceleration * seconds * seconds / 2, 0.01);
}

TEST(Sleeping, ATeleportWakesASleeperThatThenFallsFreely) {
  Simulation simulation(test::emptyWorld());
  WorldApi world(simulation);
  spawnCrate(simulation, "crate", 0, kSide / 2);
  settle(simulation, {"crate"});
  EntityState lifted = world.modelState("crate");
  lifted.pose.translation().z() += 1.0;
  ASSERT_EQ(world.setModelState("crate", lifted), "");
  const double seconds = 0.3;
  stepFor(simulation, seconds);
  EXPECT_NEAR(lifted.pose.translation().z() - heightOf(world, "crate"), kGravity * seconds * seconds / 2,
              0.01);
}

TEST(Sleeping, ACrateSlidingIntoASleeperWakesAndPushesIt) {
  Simulation simulation(test::emptyWorld());
  WorldApi world(simulation);
  spawnCrate(simulation, "sleeper", 0, kSide / 2);
  spawnCrate(simulation, "slider", -0.6, kSide / 2);
  settle(simulation, {"sleeper", "slider"});
  const double speed = 2.5, gap = 0.2;  // [m/s] thrown; [m] between their faces
  EntityState thrown = world.modelState("slider");
  thrown.linear = Eigen::Vector3d(speed, 0, 0);
  ASSERT_EQ(world.setModelState("slider", thrown), "");
  stepFor(simulation, 1.0);
  // Coulomb friction (mu 1) slows the slider over the gap; the crates then share its momentum and slide
  // together until friction stops them.
  const double together = std::sqrt(speed * speed - 2 * kGravity * gap) / 2;
  EXPECT_NEAR(world.modelState("sleeper").pose.translation().x(), together * together / (2 * kGravity), 0.01);
}

TEST(Sleeping, ASleeperFallsWhenTheCrateUnderItIsRemoved) {
  Simulation simulation(test::emptyWorld());
  WorldApi world(simulation);
  stackTwoCrates(simulation);
  const double top = heightOf(world, "top");
  ASSERT_TRUE(simulation.remove("bottom"));
  stepFor(simulation, 0.2);  // free fall: 0.196 m of its 0.4 m drop
  EXPECT_NEAR(heightOf(world, "top"), top - kGravity * 0.2 * 0.2 / 2, 0.01);
  stepFor(simulation, 0.8);
  EXPECT_NEAR(heightOf(world, "top"), kSide / 2, 0.005) << "on the ground";
}

TEST(Sleeping, ASleeperFallsWhenTheCrateUnderItIsTeleportedAway) {
  Simulation simulation(test::emptyWorld());
  WorldApi world(simulation);
  stackTwoCrates(simulation);
  const double top = heightOf(world, "top");
  EntityState moved = world.modelState("bottom");
  moved.pose.translation().x() += 3;
  ASSERT_EQ(world.setModelState("bottom", moved), "");
  stepFor(simulation, 0.2);
  EXPECT_NEAR(heightOf(world, "top"), top - kGravity * 0.2 * 0.2 / 2, 0.01) << "free fall";
}

TEST(Sleeping, RemovingACrateFarAwayLeavesASleeperAsleep) {
  Simulation simulation(test::emptyWorld());
  spawnCrate(simulation, "sleeper", 0, kSide / 2);
  spawnCrate(simulation, "far", 3, kSide / 2);
  settle(simulation, {"sleeper", "far"});
  ASSERT_TRUE(simulation.remove("far"));
  simulation.step();
  EXPECT_TRUE(sleeping(simulation, "sleeper"));
}

TEST(Sleeping, ASleeperFallsWhenTheStaticModelUnderItMovesAway) {
  const std::string shelf = "<model name=\"shelf\"><static>true</static><pose>0 0 0.5 0 0 0</pose>"
                            "<link name=\"body\"><collision name=\"box\"><geometry><box><size>1 1 0.2</size>"
                            "</box></geometry></collision></link></model>";
  const std::string sdf = "<?xml version=\"1.0\"?><sdf version=\"1.6\"><world name=\"shelf\">"
                          "<include><uri>model://ground_plane</uri></include>" + shelf + "</world></sdf>";
  Simulation simulation(parseWorld(sdf, "shelf.world", PackageResolver::fromEnvironment(), nullptr));
  WorldApi world(simulation);
  spawnCrate(simulation, "crate", 0, 0.6 + kSide / 2);
  settle(simulation, {"crate"});
  const double rest = heightOf(world, "crate");
  EntityState away = world.modelState("shelf");
  away.pose.translation().x() = 5;
  ASSERT_EQ(world.setModelState("shelf", away), "");
  stepFor(simulation, 0.2);  // free fall: 0.196 m of its 0.6 m drop
  EXPECT_NEAR(rest - heightOf(world, "crate"), kGravity * 0.2 * 0.2 / 2, 0.01);
}

TEST(Sleeping, NewGravityWakesEverySleeper) {
  Simulation simulation(test::emptyWorld());
  WorldApi world(simulation);
  spawnCrate(simulation, "crate", 0, kSide / 2);
  settle(simulation, {"crate"});
  PhysicsProperties physics = world.physicsProperties();
  physics.gravity = Eigen::Vector3d(0, 0, 1);
  world.setPhysicsProperties(physics);
  stepFor(simulation, 1.0);
  EXPECT_NEAR(heightOf(world, "crate") - kSide / 2, 0.5, 0.01);
}

TEST(Sleeping, AWorldCrateSleepsUnlessItsModelForbidsIt) {
  const std::string box = "<geometry><box><size>0.4 0.4 0.4</size></box></geometry>";
  const auto worldCrate = [&](const std::string& name, double x, const std::string& more) {
    return "<model name=\"" + name + "\"><pose>" + std::to_string(x) + " 0 0.2 0 0 0</pose>" + more +
           "<link name=\"body\"><inertial><mass>4</mass></inertial><collision name=\"box\">" + box +
           "</collision></link></model>";
  };
  const std::string sdf = "<?xml version=\"1.0\"?><sdf version=\"1.6\"><world name=\"crates\">"
                          "<include><uri>model://ground_plane</uri></include>" +
                          worldCrate("sleeper", 0, "") +
                          worldCrate("awake", 2, "<allow_auto_disable>false</allow_auto_disable>") +
                          "</world></sdf>";
  Simulation simulation(parseWorld(sdf, "crates.world", PackageResolver::fromEnvironment(), nullptr));
  stepFor(simulation, 1.5);
  EXPECT_TRUE(simulation.worldBody(1)->body().sleeping());
  EXPECT_FALSE(simulation.worldBody(2)->body().sleeping());
}

TEST(Sleeping, AModelWithJointsNeverSleeps) {
  Simulation simulation(test::emptyWorld());
  const std::string urdf = test::readFile(test::fixture("robots/two_wheeler.urdf"));
  simulation.spawn("jointed", test::parseQuietly(urdf, "two_wheeler.urdf"), {});
  stepFor(simulation, 2.5);
  EXPECT_FALSE(sleeping(simulation, "jointed"));
}

}  // namespace
}  // namespace bullet_sim
