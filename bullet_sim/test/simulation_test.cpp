// The simulator core against closed forms: robots at rest where they spawn; the lidar against analytic
// distances; bit-identical reruns, resets, spawn joint positions, several robots in one world. Stepped
// in-process, no roscore. The drives' and the pan/tilt's own tests are in their plugin folders.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "bullet_sim/common/diagnostics.h"
#include "plugins/ray_lidar/ray_lidar.h"
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

/// The distance from `origin` along `direction` to the inner walls of test_room.world (x = +-3, y = +-2).
double roomDistance(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  double t = INFINITY;
  if (direction.x() > 0) t = std::min(t, (3 - origin.x()) / direction.x());
  if (direction.x() < 0) t = std::min(t, (-3 - origin.x()) / direction.x());
  if (direction.y() > 0) t = std::min(t, (2 - origin.y()) / direction.y());
  if (direction.y() < 0) t = std::min(t, (-2 - origin.y()) / direction.y());
  return t;
}

/// The first scan of the robot's lidar.
LaserScan firstScan(Simulation& simulation, Robot& robot) {
  RayLidar* lidar = test::pluginsOf<RayLidar>(robot).at(0);
  test::stepUntil(
      simulation, [&] { return lidar->scanCount() > 0; }, 1.0, "a scan");
  return lidar->scan();
}

/// Checks every beam against the room's analytic distance, with REP 117's -inf and +inf.
void expectRoomScan(const LaserScan& scan, int* below_min = nullptr, int* beyond_max = nullptr) {
  const Eigen::Vector3d origin = scan.sensor_pose.translation();
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double angle = scan.angle_min + i * scan.angle_increment;
    const Eigen::Vector3d direction =
        scan.sensor_pose.linear() * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0);
    const double truth = roomDistance(origin, direction);
    if (truth < scan.range_min) {
      EXPECT_EQ(scan.ranges[i], -INFINITY) << "beam " << i << " truth " << truth;
      if (below_min) ++*below_min;
    } else if (truth > scan.range_max) {
      EXPECT_EQ(scan.ranges[i], INFINITY) << "beam " << i << " truth " << truth;
      if (beyond_max) ++*beyond_max;
    } else {
      EXPECT_NEAR(scan.ranges[i], truth, 0.001) << "beam " << i;
    }
  }
}

TEST(Lidar, WheelchairScanMatchesTheRoomAndNeverSeesTheChair) {
  const std::string urdf =
      test::replaceAfter(test::expandXacro("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro"),
                         "<sensor", "<stddev>0.01</stddev>", "<stddev>0</stddev>");
  Simulation simulation(test::shippedWorld("test_room.world"));
  Robot& robot =
      simulation.spawn("chair", test::parseQuietly(urdf, "chair"), {.x = 0.5, .y = -0.3, .yaw = 0.3});
  const LaserScan scan = firstScan(simulation, robot);
  ASSERT_EQ(scan.ranges.size(), 360u);
  EXPECT_EQ(scan.frame_id, "laser_Link");
  EXPECT_DOUBLE_EQ(scan.angle_increment, 6.0 / 359);
  EXPECT_DOUBLE_EQ(scan.scan_time, 1 / 5.5);
  expectRoomScan(scan);  // every beam reaches a wall: the chair's own body is not in the scan
}

TEST(Lidar, RangesBeyondMaxAreInfAndBelowMinAreMinusInf) {
  for (const double x : {0.0, 2.8}) {
    Simulation simulation(test::shippedWorld("test_room.world"));
    Robot& robot = simulation.spawn("mast",
                                    parseModel(test::readFile(test::fixture("robots/lidar_mast.urdf")),
                                               "lidar_mast.urdf", PackageResolver::fromEnvironment()),
                                    {.x = x});
    const LaserScan scan = firstScan(simulation, robot);
    ASSERT_EQ(scan.ranges.size(), 181u);
    EXPECT_DOUBLE_EQ(scan.angle_increment, M_PI / 180);
    int below_min = 0, beyond_max = 0;
    expectRoomScan(scan, &below_min, &beyond_max);
    if (x == 0.0) {
      EXPECT_GT(beyond_max, 0) << "the wall ahead is 3 m away, beyond the 2.5 m maximum";
    } else {
      EXPECT_GT(below_min, 0) << "the wall ahead is 0.2 m away, inside the 0.3 m minimum";
    }
  }
}

// A robot never stands exactly level: its scan's rays carry z components from a hair (1e-15, as settling
// leaves it) to a slope's, of either sign. Every beam still meets the walls where the room's geometry says.
TEST(Lidar, ATiltedLidarSeesTheWallsWhereTheyAre) {
  const ModelSpec mast = parseModel(test::readFile(test::fixture("robots/lidar_mast.urdf")), "lidar_mast.urdf",
                                    PackageResolver::fromEnvironment());
  for (const double tilt : {1e-15, -1e-12, 1e-9, -1e-7, 3e-7, -1e-6, 1e-5, -1e-4, 1e-3, -1e-2}) {
    for (const double x : {0.0, 2.8}) {
      Simulation simulation(test::shippedWorld("test_room.world"));
      Robot& robot = simulation.spawn("mast", mast, {.x = x, .yaw = 0.1, .roll = tilt, .pitch = tilt / 2});
      SCOPED_TRACE("tilt " + std::to_string(tilt) + " rad at x = " + std::to_string(x));
      expectRoomScan(firstScan(simulation, robot));
    }
  }
}

TEST(Lidar, MultiChannelReturnsLieOnTheRoomsWallsAndFloor) {
  Simulation simulation(test::shippedWorld("test_room.world"));
  Robot& robot =
      simulation.spawn("mast", fixtureRobot("velodyne_mast.urdf"), {.x = 0.4, .y = -0.2, .yaw = 0.3});
  RayLidar* lidar = test::pluginsOf<RayLidar>(robot).at(0);
  ASSERT_EQ(lidar->config().output, RayLidarConfig::Output::kPointCloud2);
  ASSERT_EQ(lidar->config().channels, 16);
  ASSERT_TRUE(test::stepUntil(
      simulation, [&] { return lidar->scanCount() > 0; }, 1.0, "a point cloud"));
  const PointCloud& cloud = lidar->cloud();
  // The upper channels clear the 1 m walls in places and return nothing; every other ray hits a wall or the
  // floor.
  EXPECT_GT(cloud.points.size(), 360u * 8);
  EXPECT_LT(cloud.points.size(), 360u * 16);
  std::set<int> rings;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Eigen::Vector3d p = cloud.sensor_pose * cloud.points[i].cast<double>();
    const double to_surface =
        std::min({std::abs(std::abs(p.x()) - 3), std::abs(std::abs(p.y()) - 2), std::abs(p.z())});
    ASSERT_LT(to_surface, 0.001) << "point " << i << " at " << p.transpose();
    rings.insert(cloud.rings[i]);
  }
  EXPECT_EQ(*rings.begin(), 0);
  EXPECT_EQ(*rings.rbegin(), 15);
}

TEST(Lidar, ThePluginFilenameChoosesTheMessage) {
  const std::string velodyne = test::readFile(test::fixture("robots/velodyne_mast.urdf"));
  for (const auto& [filename, output] : std::vector<std::pair<std::string, RayLidarConfig::Output>>{
           {"libgazebo_ros_velodyne_gpu_laser.so", RayLidarConfig::Output::kPointCloud2},
           {"libgazebo_ros_block_laser.so", RayLidarConfig::Output::kPointCloud},
           {"libgazebo_ros_laser.so", RayLidarConfig::Output::kLaserScan}}) {
    const std::string urdf =
        test::replaceAfter(velodyne, "<plugin", "libgazebo_ros_velodyne_laser.so", filename);
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("mast", test::parseQuietly(urdf, filename), {});
    EXPECT_EQ(test::pluginsOf<RayLidar>(robot).at(0)->config().output, output) << filename;
  }
}

struct RunResult {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<float> ranges;
};

RunResult runWheelchair(uint64_t seed, const std::string& wheel_model) {
  Simulation simulation(test::shippedWorld("test_room.world"), {.seed = seed});
  Robot& robot = simulation.spawn("chair", test::wheelchair(wheel_model), {});
  drive(simulation, *test::pluginsOf<WheeledDrive>(robot).at(0), 0.4, 0.3, 1.0);
  RunResult result;
  for (const auto& link : robot.body().spec().links) result.poses.push_back(robot.body().linkPose(link.name));
  result.ranges = test::pluginsOf<RayLidar>(robot).at(0)->scan().ranges;
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
  const LaserScan& scan = test::pluginsOf<RayLidar>(mast).at(0)->scan();
  const float ahead = scan.ranges[90];  // beam 90 of 181 points along +x, at the chair's body
  EXPECT_TRUE(std::isfinite(ahead));
  EXPECT_LT(ahead, 1.5);
  EXPECT_GT(ahead, 1.0);
  EXPECT_EQ(chair.name(), "chair");
  EXPECT_EQ(simulation.robotNames(), (std::vector<std::string>{"mast", "chair", "car"}));
}

}  // namespace
}  // namespace bullet_sim
