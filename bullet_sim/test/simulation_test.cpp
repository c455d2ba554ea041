// The simulator core: robots at rest where they spawn; bit-identical reruns, resets, spawn joint positions,
// several robots in one world. Stepped in-process, no roscore. The drives' and the pan/tilt's own tests are
// in their plugin folders.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bullet_sim/common/diagnostics.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

constexpr double kDeg = M_PI / 180;

using test::Planar;
using test::planar;

/// Runs `seconds` of sim time, re-sending (v, w) every 0.1 s as `rostopic pub -r 10` does.
void drive(Simulation& simulation, WheeledDrive& drive, double v, double w, double seconds) {
  test::stepSending(simulation, seconds, [&] { return drive.setCommand(v, w, simulation.time()); });
}

ModelSpec fixtureRobot(const std::string& file) {
  return test::parseQuietly(test::readFile(test::fixture("robots/" + file)), file);
}

/// Pose of `link` relative to where it was at spawn, in the spawn frame.
Planar travelled(const Robot& robot, const Eigen::Isometry3d& start,
                 const std::string& link = "base_footprint") {
  return planar(start.inverse() * robot.body().linkPose(link));
}

TEST(Simulation, EveryRobotRestsOnTheGroundWhereItSpawns) {
  for (const auto& wheel_model : test::kWheelModels) {
    for (auto model :
         {test::wheelchair(wheel_model), test::smartcar(wheel_model), test::yahboomcar(wheel_model)}) {
      SCOPED_TRACE(model.name + " on " + wheel_model + " wheels");
      Simulation simulation(test::shippedWorld("empty.world"));
      Robot& robot = simulation.spawn("robot", std::move(model), {.x = 1, .y = -2, .yaw = 0.7});
      const Eigen::Isometry3d start = robot.body().linkPose("base_link");
      for (int i = 0; i < 2000; ++i) simulation.step();  // 2 s
      const Eigen::Isometry3d end = robot.body().linkPose("base_link");
      // Contacts settle within Bullet's penetration allowance, well under a millimetre.
      EXPECT_NEAR(end.translation().z(), start.translation().z(), 0.001);
      const Eigen::Vector3d up = end.linear().col(2);
      EXPECT_LT(std::acos(std::min(1.0, up.z())), 0.5 * kDeg) << "roll or pitch";
      EXPECT_NEAR(end.translation().x(), 1, 0.005);
      EXPECT_NEAR(end.translation().y(), -2, 0.005);
    }
  }
}

struct RunResult {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<float> ranges;
  uint64_t shared_solves = 0;  ///< substeps whose islands the pool's threads solved side by side
};

RunResult runWheelchair(uint64_t seed, const std::string& wheel_model) {
  Simulation simulation(test::shippedWorld("test_room.world"), {.seed = seed});
  Robot& robot = simulation.spawn("chair", test::wheelchair(wheel_model), {});
  drive(simulation, *test::pluginsOf<WheeledDrive>(robot).at(0), 0.4, 0.3, 1.0);
  RunResult result;
  for (const auto& link : robot.body().spec().links) result.poses.push_back(robot.body().linkPose(link.name));
  result.ranges = robot.outputs<LaserScan>().at(0).stream->latest().ranges;
  return result;
}

TEST(Simulation, TheSameInputsAndSeedGiveABitIdenticalRun) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    const RunResult first = runWheelchair(7, wheel_model);
    const RunResult second = runWheelchair(7, wheel_model);
    ASSERT_EQ(first.poses.size(), second.poses.size());
    for (size_t i = 0; i < first.poses.size(); ++i) {
      EXPECT_EQ(first.poses[i].matrix(), second.poses[i].matrix());
    }
    EXPECT_EQ(first.ranges, second.ranges);
    EXPECT_NE(runWheelchair(8, wheel_model).ranges, first.ranges) << "the seed drives the lidar noise";
  }
}

/// Ten wheelchairs 1.5 m apart in the empty world, each driving its own circle for 1 s with its lidar
/// scanning the others; each step's scans cast in the step by `threads` (lockstep). Every robot's link poses,
/// then its latest scan.
RunResult runFleet(uint64_t seed, const std::string& wheel_model, int threads) {
  Simulation simulation(test::shippedWorld("empty.world"),
                        {.seed = seed, .threads = threads, .lockstep = true});
  constexpr int count = 10;
  std::vector<Robot*> robots;
  for (int k = 0; k < count; ++k) {
    const std::string name = "chair" + std::to_string(k);
    robots.push_back(&simulation.spawn(name, test::wheelchair(wheel_model),
                                       {.x = 1.5 * (k % 5), .y = 1.5 * (k / 5), .yaw = 0.3 * k,
                                        .robot_namespace = name}));
  }
  test::stepSending(simulation, 1.0, [&] {
    for (size_t k = 0; k < robots.size(); ++k) {
      if (!test::pluginsOf<WheeledDrive>(*robots[k])
               .at(0)
               ->setCommand(0.2 + 0.02 * k, 0.3, simulation.time()))
        return false;
    }
    return true;
  });
  RunResult result;
  for (const Robot* robot : robots) {
    for (const auto& link : robot->body().spec().links)
      result.poses.push_back(robot->body().linkPose(link.name));
  }
  for (const Robot* robot : robots) {
    const auto& ranges = robot->outputs<LaserScan>().at(0).stream->latest().ranges;
    result.ranges.insert(result.ranges.end(), ranges.begin(), ranges.end());
  }
  result.shared_solves = simulation.sharedSolves();
  return result;
}

TEST(Simulation, TenRobotsRerunBitIdenticallyWhateverThreadsCastTheirRaysAndSolveTheirIslands) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    const RunResult first = runFleet(7, wheel_model, 2);
    for (const int threads : {2, 1, 3}) {
      SCOPED_TRACE(std::to_string(threads) + " threads");
      const RunResult again = runFleet(7, wheel_model, threads);
      ASSERT_EQ(first.poses.size(), again.poses.size());
      for (size_t i = 0; i < first.poses.size(); ++i)
        EXPECT_EQ(first.poses[i].matrix(), again.poses[i].matrix());
      EXPECT_EQ(first.ranges, again.ranges);
      // Ten robots on contact wheels are ten islands worth sharing (their wheels' contact rows).
      if (wheel_model == "contact") {
        EXPECT_EQ(again.shared_solves > 0, threads > 1);
      }
    }
    // The robots saw each other: in the empty world, only they return a finite range.
    EXPECT_GT(
        std::count_if(first.ranges.begin(), first.ranges.end(), [](float r) { return std::isfinite(r); }),
        100);
    EXPECT_NE(runFleet(8, wheel_model, 2).ranges, first.ranges) << "the seed drives the lidar noise";
  }
}

/// Every scan of a fleet as it appears: its robot, its stamp, its ranges and the step after which it
/// appeared.
struct SeenScan {
  size_t robot = 0;
  double stamp = 0;
  std::vector<float> ranges;
  uint64_t seen_after = 0;  ///< steps
  bool operator==(const SeenScan& other) const {  // what was measured, not when it was seen
    return robot == other.robot && stamp == other.stamp && ranges == other.ranges;
  }
};

/// Four wheelchairs driving circles for 2 s, their lidars seeing each other, with the rays cast in lockstep
/// or behind physics: every scan in the order they appeared, and every link's pose at the end. Robot k is
/// spawned at step k * `stagger`, so that with a stagger the lidars are due in different steps.
std::pair<std::vector<SeenScan>, std::vector<Eigen::Isometry3d>> scansOfFleet(bool lockstep, int stagger) {
  Simulation simulation(test::shippedWorld("empty.world"), {.seed = 3, .lockstep = lockstep});
  std::vector<Robot*> robots;
  std::vector<uint64_t> counted;
  const auto spawn_due = [&](int step) {
    for (int k = static_cast<int>(robots.size()); k < 4 && k * stagger <= step; ++k) {
      robots.push_back(&simulation.spawn("chair" + std::to_string(k), test::wheelchair("raycast"),
                                         {.x = 1.5 * (k % 2), .y = 1.5 * (k / 2), .yaw = 0.5 * k}));
      counted.push_back(0);
    }
  };
  std::vector<SeenScan> scans;
  const auto collect = [&] {
    for (size_t k = 0; k < robots.size(); ++k) {
      const Stream<LaserScan>& stream = *robots[k]->outputs<LaserScan>().at(0).stream;
      if (stream.count() == counted[k]) continue;
      EXPECT_EQ(stream.count(), counted[k] + 1) << "a scan was overwritten before it was seen";
      counted[k] = stream.count();
      scans.push_back({k, stream.latest().stamp, stream.latest().ranges, simulation.steps()});
    }
  };
  for (int step = 0; step < 2000; ++step) {  // 2 s, the commands re-sent at 10 Hz
    spawn_due(step);
    for (size_t k = 0; k < robots.size() && step % 100 == 0; ++k)
      test::pluginsOf<WheeledDrive>(*robots[k]).at(0)->setCommand(0.3, 0.3 + 0.1 * k, simulation.time());
    simulation.step();
    collect();
  }
  simulation.finishCasts();
  collect();
  std::vector<Eigen::Isometry3d> poses;
  for (const Robot* robot : robots) {
    for (const auto& link : robot->body().spec().links) poses.push_back(robot->body().linkPose(link.name));
  }
  return {scans, poses};
}

/// The scans of the fleet above cast behind physics are those cast in lockstep, each seen by the step its
/// lidar is due again in.
void expectBehindAsInLockstep(int stagger) {
  const auto [in_step, in_step_poses] = scansOfFleet(true, stagger);
  const auto [behind, behind_poses] = scansOfFleet(false, stagger);
  ASSERT_EQ(behind_poses.size(), in_step_poses.size());
  for (size_t i = 0; i < in_step_poses.size(); ++i)
    EXPECT_EQ(behind_poses[i].matrix(), in_step_poses[i].matrix()) << "physics is the same";
  ASSERT_GE(in_step.size(), 4u * 9);  // 2 s of a lidar at 5.5 Hz, each robot's
  std::vector<SeenScan> sorted = behind;  // seen later, the order of robots may change
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const SeenScan& a, const SeenScan& b) { return a.stamp < b.stamp; });
  EXPECT_EQ(sorted, in_step);
  size_t later = 0;
  for (size_t i = 0; i < in_step.size() && i < sorted.size(); ++i) {
    const double step = 0.001;
    const double lag = static_cast<double>(sorted[i].seen_after) * step - sorted[i].stamp;
    EXPECT_NEAR(static_cast<double>(in_step[i].seen_after) * step, in_step[i].stamp, 1e-9)
        << "seen at its step";
    EXPECT_GE(lag, -1e-9);
    EXPECT_LE(lag, 1 / 5.5 + step + 1e-9) << "seen by the step the lidar is due again in";
    later += lag > 1e-9;
  }
  ::testing::Test::RecordProperty("scans_seen_after_their_step_" + std::to_string(stagger),
                                  static_cast<int>(later));
}

TEST(Simulation, ScansCastBehindPhysicsAreTheLockstepScansSeenByTheNextDueStep) {
  expectBehindAsInLockstep(0);
}

TEST(Simulation, ScansDueInDifferentStepsQueueBehindPhysicsAndAreTheLockstepScans) {
  // Spawned a step more than the 5.5 Hz lidars' period apart, each is due a step after the one before: a
  // robot's cast queues on the lane behind another's.
  expectBehindAsInLockstep(183);
}

TEST(Simulation, ALidarDueEveryStepBehindPhysicsDeliversEveryScanInAStepOfItsOwn) {
  std::string urdf = test::readFile(test::fixture("robots/lidar_mast.urdf"));
  urdf.replace(urdf.find("<update_rate>10<"), 16, "<update_rate>0<");  // every step
  Simulation simulation(test::shippedWorld("empty.world"), {.lockstep = false});
  Robot& mast = simulation.spawn("mast", test::parseQuietly(urdf, "lidar_mast.urdf"), {});
  const Stream<LaserScan>& scans = *mast.outputs<LaserScan>().at(0).stream;
  uint64_t seen = 0;
  for (int i = 0; i < 500; ++i) {
    simulation.step();
    if (scans.count() == seen) continue;
    ASSERT_EQ(scans.count(), seen + 1) << "a scan was overwritten before the step ended, at step " << i + 1;
    ++seen;
    EXPECT_NEAR(scans.latest().stamp, 0.001 * static_cast<double>(seen), 1e-9)
        << "scans in order, none skipped";
  }
  EXPECT_GE(seen, 499u) << "at most one step behind";
}

TEST(Simulation, ScansBehindPhysicsAreDeliveredBeforeTheRaysMoveFromOutside) {
  Simulation simulation(test::shippedWorld("empty.world"), {.lockstep = false});
  Robot& mast = simulation.spawn("mast", fixtureRobot("lidar_mast.urdf"), {});
  const Stream<LaserScan>& scans = *mast.outputs<LaserScan>().at(0).stream;
  const auto step_to = [&](uint64_t steps) {  // the mast's 10 Hz lidar casts at every 100th step
    while (simulation.steps() < steps) simulation.step();
  };
  const auto ahead = [&] { return scans.latest().ranges[90]; };  // beam 90 of 181 points along +x
  step_to(100);  // the scan of 0.1 s may still be cast
  simulation.spawn("chair", test::wheelchair(), {.x = 1.5, .yaw = M_PI / 2});  // joins the ray caster
  EXPECT_NEAR(scans.latest().stamp, 0.1, 1e-9);
  EXPECT_FALSE(std::isfinite(ahead())) << "cast before the chair came";
  step_to(200);
  EXPECT_TRUE(simulation.remove("chair"));
  EXPECT_NEAR(scans.latest().stamp, 0.2, 1e-9);
  EXPECT_GT(ahead(), 1.0) << "cast while the chair was there";
  EXPECT_LT(ahead(), 1.5);
  step_to(300);
  simulation.refreshRays();  // as after a teleport
  EXPECT_NEAR(scans.latest().stamp, 0.3, 1e-9);
  EXPECT_FALSE(std::isfinite(ahead())) << "cast after the chair left";
  step_to(400);
  simulation.resetWorld();
  EXPECT_NEAR(scans.latest().stamp, 0.4, 1e-9);
}

TEST(Simulation, InitialJointPositionsApplyAtSpawnAndAfterAReset) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    SpawnPose pose;
    pose.joints = {{"front_left_joint", 1.0}, {"rear_right_joint", 0.5}};
    Robot& robot = simulation.spawn("chair", test::wheelchair(wheel_model), pose);
    const auto position = [&](const char* joint) {
      return robot.body().jointPosition(robot.body().jointIndex(joint));
    };
    EXPECT_NEAR(position("front_left_joint"), 1.0, 1e-9);
    EXPECT_NEAR(position("rear_right_joint"), 0.5, 1e-9);
    EXPECT_NEAR(position("front_right_joint"), 0.0, 1e-9);
    drive(simulation, *test::pluginsOf<WheeledDrive>(robot).at(0), 0.5, 0, 0.5);
    simulation.resetSimulation();
    EXPECT_NEAR(position("front_left_joint"), 1.0, 1e-9);
    EXPECT_NEAR(position("rear_right_joint"), 0.5, 1e-9);

    SpawnPose typo;
    typo.joints = {{"front_left_jiont", 1.0}};
    try {
      simulation.spawn("other", test::wheelchair(wheel_model), typo);
      ADD_FAILURE() << "a misspelt joint was accepted";
    } catch (const SpecError& e) {
      EXPECT_THAT(std::string(e.what()),
                  HasSubstr("[front_left_jiont], which is not a moving joint (did you mean "
                            "[front_left_joint]?)"));
    }
  }
}

TEST(Simulation, ResetSimulationRestoresPosesAndTime) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("chair", test::wheelchair(wheel_model), {.x = 1, .yaw = 0.5});
    const Eigen::Isometry3d start = robot.body().linkPose("base_footprint");
    drive(simulation, *test::pluginsOf<WheeledDrive>(robot).at(0), 0.5, 0.5, 1.0);
    ASSERT_GT((robot.body().linkPose("base_footprint").translation() - start.translation()).norm(), 0.2);
    simulation.resetSimulation();
    EXPECT_EQ(simulation.time(), 0.0);
    EXPECT_TRUE(robot.body().linkPose("base_footprint").isApprox(start, 1e-9));
    simulation.step();
    EXPECT_DOUBLE_EQ(simulation.time(), simulation.stepSize());
  }
}

TEST(Simulation, EachIgnoredOrSuspectTagIsSaidOnceAtLoad) {
  Simulation simulation(test::shippedWorld("empty.world"));
  std::vector<std::string> warnings;
  ModelSpec model = parseModel(test::readFile(test::fixture("robots/load_messages.urdf")),
                               "load_messages.urdf", PackageResolver::fromEnvironment(), &warnings);
  simulation.spawn("robot", std::move(model), {}, &warnings);
  const auto said = [&](const std::string& text) {
    return std::count_if(warnings.begin(), warnings.end(),
                         [&](const std::string& w) { return w.find(text) != std::string::npos; });
  };
  EXPECT_EQ(said("<legacyMode> is a Kinetic tag"), 1);
  EXPECT_EQ(said("plugin [drive] <wheelSeperation> is not a tag this plugin knows"), 1);
  EXPECT_EQ(said("filename [libgazebo_ros_bumper.so] is not a plugin bullet_sim simulates"), 1);
  EXPECT_EQ(said("sensor [bumper] on link [balloon] has no <plugin>"), 1);
  EXPECT_EQ(warnings.size(), 4u);
}

TEST(Simulation, TurnGravityOffHoldsALinkUpAndGravityPullsTheRest) {
  for (const bool weightless : {false, true}) {
    std::string urdf = test::readFile(test::fixture("robots/minimal.urdf"));
    if (weightless) {
      urdf = test::replaceAfter(
          urdf, "</link>", "</robot>",
          "<gazebo reference=\"base_link\"><turnGravityOff>true</turnGravityOff></gazebo></robot>");
    }
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("box", test::parseQuietly(urdf, "box"), {.z = 1.0});
    for (int i = 0; i < 300; ++i) simulation.step();  // 0.3 s
    const double fallen = 1.0 - robot.body().linkPose("base_link").translation().z();
    if (weightless) {
      EXPECT_NEAR(fallen, 0, 1e-9);
    } else {
      // Free fall under Bullet's symplectic Euler: after n steps of dt, g dt^2 n (n + 1) / 2.
      const double n = 300, dt = simulation.stepSize();
      EXPECT_NEAR(fallen, 9.81 * dt * dt * n * (n + 1) / 2, 1e-9);
    }
  }
}

TEST(Simulation, RobotsShareTheWorldAndSeeEachOther) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& mast = simulation.spawn("mast", fixtureRobot("lidar_mast.urdf"), {});
  Robot& chair = simulation.spawn("chair", test::wheelchair(), {.x = 1.5, .yaw = M_PI / 2});
  Robot& car = simulation.spawn("car", test::smartcar(), {.x = -2});
  const Eigen::Isometry3d car_start = car.body().linkPose("base_footprint");
  auto* drive = test::pluginsOf<WheeledDrive>(car).at(0);
  for (int i = 0; i < 1000; ++i) {
    if (i % 100 == 0) drive->setCommand(-0.2, 0, simulation.time());
    simulation.step();
  }
  EXPECT_LT(travelled(car, car_start).x, -0.15) << "each robot follows its own commands";
  const LaserScan& scan = mast.outputs<LaserScan>().at(0).stream->latest();
  const float ahead = scan.ranges[90];  // beam 90 of 181 points along +x, at the chair's body
  EXPECT_TRUE(std::isfinite(ahead));
  EXPECT_LT(ahead, 1.5);
  EXPECT_GT(ahead, 1.0);
  EXPECT_EQ(chair.name(), "chair");
  EXPECT_EQ(simulation.robotNames(), (std::vector<std::string>{"mast", "chair", "car"}));
}

// Two raycast wheelchairs driving head-on into each other push alike and stall where they meet, whichever
// was spawned first: where their rims touched, the second robot's rim used to overwrite the first's friction,
// and the first pushed the second back at full speed.
TEST(Simulation, TwoRobotsDrivingHeadOnStallWhereTheyMeetWhicheverCameFirst) {
  for (const bool ahead_first : {true, false}) {
    SCOPED_TRACE(ahead_first ? "the one at x = 0 spawned first" : "the one at x = 1.6 m spawned first");
    Simulation simulation(test::shippedWorld("empty.world"));
    const auto spawn = [&](const std::string& name, double x, double yaw) {
      return &simulation.spawn(name, test::wheelchair("raycast"),
                               {.x = x, .yaw = yaw, .robot_namespace = name});
    };
    Robot* west = ahead_first ? spawn("west", 0, 0) : nullptr;
    Robot* east = spawn("east", 1.6, M_PI);
    if (!west) west = spawn("west", 0, 0);
    const auto x = [](const Robot& robot) {
      return robot.body().linkPose(robot.body().spec().root).translation().x();
    };
    test::stepSending(simulation, 4.0, [&] {
      return test::pluginsOf<WheeledDrive>(*west).at(0)->setCommand(0.3, 0, simulation.time()) &&
             test::pluginsOf<WheeledDrive>(*east).at(0)->setCommand(0.3, 0, simulation.time());
    });
    // They meet after about 1.4 s; by 4 s a robot pushed back at 0.3 m/s would be 0.75 m off.
    EXPECT_NEAR(x(*west) + x(*east), 1.6, 0.02)
        << "west at " << x(*west) << " m, east at " << x(*east) << " m";
  }
}

}  // namespace
}  // namespace bullet_sim

