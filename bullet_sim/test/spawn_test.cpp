// Spawning into a world that was saved with the robot in it (seed 000's pitfall: "two robots appear"): the
// copy is found by its collision shapes where the robot spawns, and the spawn is refused naming it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

using test::fixture;
using test::readFile;

WorldSpec savedWorld() {
  std::vector<std::string> warnings;  // the saved robot is not static and has joints: both said, both fine
  return loadWorld(fixture("worlds/saved_with_robot.world"), PackageResolver::fromEnvironment(), &warnings);
}

ModelSpec robotFixture(const std::string& file) {
  return parseModel(readFile(fixture("robots/" + file)), file, PackageResolver::fromEnvironment());
}

SpawnPose at(double x, double y) {
  SpawnPose pose;
  pose.x = x;
  pose.y = y;
  return pose;
}

/// The message of the SpecError that the spawn throws, or "" when the robot spawns.
std::string spawnError(Simulation& simulation, const std::string& name, ModelSpec model,
                       const SpawnPose& pose) {
  try {
    simulation.spawn(name, std::move(model), pose);
  } catch (const SpecError& e) {
    return e.what();
  }
  return "";
}

TEST(Spawn, RefusesAWorldSavedWithTheRobotWhereItSpawns) {
  Simulation simulation(savedWorld());
  const std::string error = spawnError(simulation, "robot", robotFixture("two_wheeler.urdf"), at(0, 0));
  EXPECT_THAT(error,
              HasSubstr("the world's model [two_wheeler] has the collision shapes of robot [robot] where it "
                        "spawns: was the world saved with the robot in it? Remove [two_wheeler] from the "
                        ".world file"));
  EXPECT_TRUE(simulation.robotNames().empty()) << "a refused robot leaves nothing behind";
  simulation.step();
}

TEST(Spawn, RefusesAWorldModelWithTheRobotsName) {
  Simulation simulation(savedWorld());
  const std::string error = spawnError(simulation, "two_wheeler", robotFixture("two_wheeler.urdf"), at(3, 0));
  EXPECT_THAT(error, HasSubstr("the world already holds a model named [two_wheeler]"));
}

TEST(Spawn, AcceptsTheRobotAwayFromTheSavedCopy) {
  Simulation simulation(savedWorld());
  EXPECT_EQ(spawnError(simulation, "robot", robotFixture("two_wheeler.urdf"), at(3, 0)), "");
  EXPECT_EQ(simulation.robotNames(), std::vector<std::string>{"robot"});
}

TEST(Spawn, DoesNotTakeAnotherRobotForTheCopy) {
  Simulation simulation(savedWorld());
  EXPECT_EQ(spawnError(simulation, "box", robotFixture("minimal.urdf"), at(0.3, -0.2)), "");
}

}  // namespace
}  // namespace bullet_sim
