// The lidar plugins against analytic distances in test_room.world: REP 117's infinities, tilted scans,
// multi-channel clouds, and the message each plugin filename chooses. Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "plugins/ray_lidar/ray_lidar.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

ModelSpec fixtureRobot(const std::string& file) {
  return test::parseQuietly(test::readFile(test::fixture("robots/" + file)), file);
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
      simulation, [&] { return test::countOf<LaserScan>(*lidar) > 0; }, 1.0, "a scan");
  return test::latestOf<LaserScan>(*lidar);
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

// Gazebo takes a <max_angle> below <min_angle>: its beams step down from min_angle, and the scan says so
// with a negative angle_increment. Each beam still meets the wall its angle points at.
TEST(Lidar, AMaxAngleBelowMinAngleScansDownwardsWithAWarning) {
  const std::string urdf = test::replaceAfter(
      test::readFile(test::fixture("robots/lidar_mast.urdf")), "<horizontal>",
      "<min_angle>-1.5707963267948966</min_angle><max_angle>1.5707963267948966</max_angle>",
      "<min_angle>1.2</min_angle><max_angle>-0.6</max_angle>");
  std::vector<std::string> warnings;
  const ModelSpec mast = parseModel(urdf, "lidar_mast.urdf", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_THAT(warnings, testing::ElementsAre(testing::HasSubstr(
                            "<horizontal> <max_angle> is below <min_angle>: the beams step from min_angle "
                            "down to max_angle, as Gazebo's do")));
  Simulation simulation(test::shippedWorld("test_room.world"));
  const LaserScan scan = firstScan(simulation, simulation.spawn("mast", mast, {.x = 0.4, .yaw = 0.25}));
  ASSERT_EQ(scan.ranges.size(), 181u);
  EXPECT_DOUBLE_EQ(scan.angle_min, 1.2);
  EXPECT_DOUBLE_EQ(scan.angle_max, -0.6);
  EXPECT_DOUBLE_EQ(scan.angle_increment, -1.8 / 180);
  expectRoomScan(scan);
  const Eigen::Vector3d first_beam(std::cos(1.2), std::sin(1.2), 0);
  const double first = roomDistance(scan.sensor_pose.translation(), scan.sensor_pose.linear() * first_beam);
  EXPECT_NEAR(scan.ranges.front(), first, 0.001) << "the first beam points at min_angle";
}

// A robot never stands exactly level: its scan's rays carry z components from a hair (1e-15, as settling
// leaves it) to a slope's, of either sign. Every beam still meets the walls where the room's geometry says.
TEST(Lidar, ATiltedLidarSeesTheWallsWhereTheyAre) {
  const ModelSpec mast = parseModel(test::readFile(test::fixture("robots/lidar_mast.urdf")),
                                    "lidar_mast.urdf", PackageResolver::fromEnvironment());
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
      simulation, [&] { return test::countOf<PointCloud>(*lidar) > 0; }, 1.0, "a point cloud"));
  const PointCloud& cloud = test::latestOf<PointCloud>(*lidar);
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

}  // namespace
}  // namespace bullet_sim
