// walled_boxes.world (issue 32's 20 x 20 m walled world of 200 loose boxes) with wheelchairs driving their
// circles into the boxes, in-process: every box stays inside the walls and on the ground, none flies, and
// the robots stay upright. Timings are bench's to print:
// bench --robots 20 --world walled_boxes.world --spacing 4.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "bench/bench_fleet.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

constexpr double kBoxSide = 0.4;     ///< [m] the world's boxes are cubes of this side
constexpr double kWalls = 10;        ///< [m] the walls' inner faces at x, y = +-kWalls
constexpr double kReach = 0.46;      ///< [m] the wheelchair's farthest point from its base frame (its lidar)
constexpr double kPushed = 0.01;     ///< [m] a box that moved this far was struck (or pushed by one)
/// [m] A box resting on the ground, spawned touching it, moves less; a contact lets a box into what it
/// touches by less.
constexpr double kSettling = 0.002;
/// [m] The highest a cube's centre can rise while it still touches the ground: balanced on a corner,
/// s sqrt(3) / 2 over the s / 2 it rests at. Above it, a box has left the ground: it flew. (A box pushed at
/// the seat block, 0.28 m up, above its half height, tips over an edge, rising s (sqrt(2) - 1) / 2 = 8.3 cm.)
const double kCornerRise = kBoxSide * (std::sqrt(3.0) - 1) / 2;
/// [rad] A wheelchair leaning 5 degrees has a drive wheel 5.7 cm off the ground (its track is 0.65 m);
/// bumping 4 kg boxes at 0.3 m/s never lifts one that far.
constexpr double kUprightTilt = 5 * M_PI / 180;

/// Four wheelchairs driving for `seconds`, at four of the world's 20 robot places (x 4, 8; y 2, 6), of
/// bench --robots 20 --spacing 4, whose circles meet boxes soonest; the world keeps every box centre at least
/// 1 m from them.
FleetOptions fourWheelchairs(double seconds) {
  FleetOptions options;
  options.urdf = test::expandXacro("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro");
  options.source = "smartwheelchair_model.urdf.xacro";
  options.duration = seconds;
  options.spacing = 4;
  options.origin.x = 6;
  options.origin.y = 4;
  return options;
}

TEST(WalledBoxes, BoxesStayInsideTheWallsOnTheGroundAndTheWheelchairsUpright) {
  std::vector<std::string> warnings;
  const FleetRun run = driveFleet(test::shippedWorld("walled_boxes.world"), 4, fourWheelchairs(3), &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  ASSERT_EQ(run.loose.size(), 200u);
  ASSERT_EQ(run.robots.size(), 4u);
  // Every robot started free of the boxes: nothing of it within a box's half diagonal of a box's centre.
  EXPECT_GT(run.start_clearance, kReach + kBoxSide / std::sqrt(2.0));

  int struck = 0;
  for (const LooseBodyTrack& box : run.loose) {
    SCOPED_TRACE(box.name);
    EXPECT_NEAR(box.start.z(), kBoxSide / 2, 1e-9);
    // Never through or into a wall, never under the ground.
    EXPECT_FALSE(box.escaped);
    // A box against a wall has its centre half a side from it, less what the contact lets it in.
    EXPECT_LT(std::abs(box.end.x()), kWalls - kBoxSide / 2 + kSettling);
    EXPECT_LT(std::abs(box.end.y()), kWalls - kBoxSide / 2 + kSettling);
    EXPECT_GT(box.z_min, kBoxSide / 2 - kSettling);  // no box sinks into the ground
    if (box.moved_max > kPushed) {
      ++struck;
      EXPECT_LT(box.z_max - box.start.z(), kCornerRise + kSettling);
    } else {
      EXPECT_LT(box.z_max - box.start.z(), kSettling);  // a box nobody touched stays where it lies
    }
  }
  // The drive struck boxes, or the test shows nothing.
  EXPECT_GT(struck, 0);
  for (const RobotTrack& robot : run.robots) {
    EXPECT_LT(robot.tiltMax(), kUprightTilt);
    EXPECT_LT(robot.rise_max, kSettling);
    EXPECT_LT(robot.sink_max, kSettling);  // nor through the floor
  }
}

/// fourWheelchairs driving into the boxes for `seconds` on `threads` threads, their scans in lockstep.
FleetRun driveIntoBoxes(double seconds, int threads) {
  FleetOptions options = fourWheelchairs(seconds);
  options.threads = threads;
  options.lockstep = true;
  std::vector<std::string> warnings;
  return driveFleet(test::shippedWorld("walled_boxes.world"), 4, options, &warnings);
}

// Each step's islands (here 200 boxes on the ground, and the wheelchairs) are solved side by side on two
// threads, each with a solver of its own; islands share no body, so the run is the same to the last bit.
TEST(WalledBoxes, TheRunIsBitIdenticalWhetherOneThreadOrTwoSolveTheIslands) {
  const FleetRun alone = driveIntoBoxes(1, 1);
  const FleetRun shared = driveIntoBoxes(1, 2);
  EXPECT_EQ(alone.shared_solves, 0);
  // The boxes are worth sharing until they sleep, a second after the spawn: half of the drive.
  EXPECT_GT(shared.shared_solves, 0.4);
  ASSERT_EQ(alone.loose.size(), shared.loose.size());
  for (size_t k = 0; k < alone.loose.size(); ++k) {
    EXPECT_EQ(alone.loose[k].end, shared.loose[k].end) << alone.loose[k].name;
    EXPECT_EQ(alone.loose[k].z_max, shared.loose[k].z_max) << alone.loose[k].name;
  }
  ASSERT_EQ(alone.end.size(), shared.end.size());
  for (size_t k = 0; k < alone.end.size(); ++k) {
    EXPECT_EQ(alone.end[k].x, shared.end[k].x);
    EXPECT_EQ(alone.end[k].y, shared.end[k].y);
    EXPECT_EQ(alone.end[k].yaw, shared.end[k].yaw);
  }
}

/// A loose 0.4 m box named `name` with its centre at `pose`.
std::string looseBox(const std::string& name, const std::string& pose) {
  return "<model name='" + name + "'><pose>" + pose +
         "</pose><link name='link'><inertial><mass>4</mass></inertial><collision name='c'><geometry><box>"
         "<size>0.4 0.4 0.4</size></box></geometry></collision></link></model>";
}

TEST(WalledBoxes, TheWatchSeesABoxOutsideTheWallsInsideOneOrUnderTheGround) {
  // Two walls 0.1 m thick, their inner faces at x = +-2; a box between them, one beyond the east wall, one
  // with its centre in the west wall, one under the ground.
  const std::string sdf =
      "<sdf version='1.6'><world name='w'><model name='ground'><static>true</static><link name='link'>"
      "<collision name='c'><geometry><plane><normal>0 0 1</normal></plane></geometry></collision>"
      "</link></model><model name='walls'><static>true</static>"
      "<link name='east'><pose>2.05 0 0.5 0 0 0</pose><collision name='c'><geometry><box>"
      "<size>0.1 4 1</size></box></geometry></collision></link>"
      "<link name='west'><pose>-2.05 0 0.5 0 0 0</pose><collision name='c'><geometry><box>"
      "<size>0.1 4 1</size></box></geometry></collision></link></model>" +
      looseBox("inside", "0 0 0.2 0 0 0") + looseBox("beyond", "3 0 0.2 0 0 0") +
      looseBox("in_wall", "-2.05 1 0.2 0 0 0") + looseBox("under", "1 1 -0.3 0 0 0") + "</world></sdf>";
  Simulation simulation(parseWorld(sdf, "watch_test.world", PackageResolver::fromEnvironment(), nullptr));
  const FleetWatch watch(simulation, {});
  ASSERT_EQ(watch.loose().size(), 4u);
  EXPECT_FALSE(watch.loose()[0].escaped);
  for (size_t k = 1; k < 4; ++k) EXPECT_TRUE(watch.loose()[k].escaped) << watch.loose()[k].name;
}

}  // namespace
}  // namespace bullet_sim
