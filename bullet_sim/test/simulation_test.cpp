// The simulator core against closed forms: robots at rest, driving straight, turning, on arcs; bit-identical
// reruns. Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model_geometry.h"
#include "plugins/joint_position/joint_position.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

constexpr double kDeg = M_PI / 180;

using test::angleDifference;
using test::Planar;
using test::planar;

/// The unicycle driven by the rim speeds a WheeledDrive commands: each wheel's speed steps towards its target
/// by at most acceleration * period at every update (every `period` s, the first one period after the start).
Planar rampedUnicycle(double v, double w, double seconds, double separation, double acceleration,
                      double period) {
  Planar pose{0, 0, 0};
  double left = 0, right = 0;
  const double dt = 1e-4;
  double next_update = period;
  for (double t = 0; t < seconds - dt / 2; t += dt) {
    if (t + dt / 2 >= next_update) {
      const auto ramp = [&](double& speed, double target) {
        const double step = acceleration > 0 ? acceleration * period : INFINITY;
        speed += std::clamp(target - speed, -step, step);
      };
      ramp(left, v - w * separation / 2);
      ramp(right, v + w * separation / 2);
      next_update += period;
    }
    const double speed = (left + right) / 2;
    const double turn = (right - left) / separation;
    pose.x += speed * std::cos(pose.yaw + turn * dt / 2) * dt;
    pose.y += speed * std::sin(pose.yaw + turn * dt / 2) * dt;
    pose.yaw += turn * dt;
  }
  return pose;
}

/// Runs `seconds` of sim time, re-sending (v, w) every 0.1 s as `rostopic pub -r 10` does.
void drive(Simulation& simulation, WheeledDrive& drive, double v, double w, double seconds) {
  const auto steps = std::lround(seconds / simulation.stepSize());
  const auto resend = std::lround(0.1 / simulation.stepSize());
  for (long i = 0; i < steps; ++i) {
    if (i % resend == 0) {
      ASSERT_TRUE(drive.setCommand(v, w, simulation.time()));
    }
    simulation.step();
  }
}

ModelSpec fixtureRobot(const std::string& file) {
  return test::parseQuietly(test::readFile(test::fixture("robots/" + file)), file);
}

/// Pose of `link` relative to where it was at spawn, in the spawn frame.
Planar travelled(const Robot& robot, const Eigen::Isometry3d& start,
                 const std::string& link = "base_footprint") {
  return planar(start.inverse() * robot.body().linkPose(link));
}

/// The frame a unicycle model describes: base_footprint moved to the midpoint of the drive wheels (the chair
/// turns about its drive axle, 0.125 m ahead of base_footprint).
Eigen::Isometry3d axleFrame(const Robot& robot, const WheeledDrive& drive) {
  const ModelSpec& model = robot.body().spec();
  const Eigen::Isometry3d base = robot.body().linkPose(drive.config().robot_base_frame);
  Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();
  for (const auto& joint : {drive.config().left_joints.at(0), drive.config().right_joints.at(0)}) {
    midpoint += 0.5 * (base.inverse() * robot.body().linkPose(model.joint(joint)->child)).translation();
  }
  midpoint.z() = 0;
  return base * Eigen::Translation3d(midpoint);
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

class WheelchairDrive : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    robot_ = &simulation_.spawn("wheelchair", test::wheelchair(GetParam()), {});
    drive_ = test::pluginsOf<WheeledDrive>(*robot_).at(0);
    start_ = axleFrame(*robot_, *drive_);
  }
  /// Where the drive axle has gone since spawn, in the spawn frame.
  Planar travelled() const { return planar(start_.inverse() * axleFrame(*robot_, *drive_)); }
  Planar oracle(double v, double w, double seconds) const {
    const DriveConfig& config = drive_->config();
    return rampedUnicycle(v, w, seconds, config.wheel_separation, config.acceleration,
                          1.0 / config.update_rate);
  }

  Simulation simulation_{test::shippedWorld("empty.world")};
  Robot* robot_ = nullptr;
  WheeledDrive* drive_ = nullptr;
  Eigen::Isometry3d start_;
};

TEST_P(WheelchairDrive, StraightLineFollowsTheRampedCommand) {
  drive(simulation_, *drive_, 0.5, 0, 4.0);
  const Planar expected = oracle(0.5, 0, 4.0);
  const Planar actual = travelled();
  // The 1.8 m/s^2 ramp leaves the chair v^2 / 2a = 0.069 m behind an instant start after 4 s, and updating at
  // 100 Hz another v * 5 ms.
  EXPECT_NEAR(2.0 - expected.x, 0.0694 + 0.0025, 0.0005);
  EXPECT_NEAR(actual.x, expected.x, 0.02);
  EXPECT_LT(std::abs(actual.y), 0.02);
  EXPECT_LT(std::abs(actual.yaw), 1 * kDeg);
}

TEST_P(WheelchairDrive, TurnsInPlaceCounterClockwiseForPositiveAngular) {
  drive(simulation_, *drive_, 0, 0.5, M_PI);
  const Planar expected = oracle(0, 0.5, M_PI);
  const Planar actual = travelled();
  EXPECT_NEAR(expected.yaw, M_PI / 2, 2 * kDeg);  // the ramp costs only a little of the quarter turn
  EXPECT_NEAR(angleDifference(actual.yaw, expected.yaw), 0, 2 * kDeg);
  EXPECT_LT(std::hypot(actual.x, actual.y), 0.05);
}

TEST_P(WheelchairDrive, ArcMatchesTheUnicycle) {
  const double seconds = 10;
  drive(simulation_, *drive_, 0.5, 0.3, seconds);
  const Planar expected = oracle(0.5, 0.3, seconds);
  const Planar actual = travelled();
  const double path = 0.5 * seconds;
  EXPECT_LT(std::hypot(actual.x - expected.x, actual.y - expected.y), 0.03 * path);
  EXPECT_NEAR(angleDifference(actual.yaw, expected.yaw), 0, 0.03 * 0.3 * seconds);
}

TEST_P(WheelchairDrive, OdometryFromTheWorldSourceIsTheBasePose) {
  drive(simulation_, *drive_, 0.5, 0.3, 1.0);
  const Odometry& odometry = drive_->odometry();
  EXPECT_EQ(drive_->odometryCount(), 100u);  // 100 Hz for 1 s
  EXPECT_DOUBLE_EQ(odometry.stamp, simulation_.time());
  EXPECT_TRUE(odometry.pose.isApprox(robot_->body().linkPose("base_footprint"), 1e-12));
  EXPECT_NEAR(odometry.linear_velocity.x(), 0.5, 0.02);
  EXPECT_NEAR(odometry.angular_velocity.z(), 0.3, 0.02);
}

TEST_P(WheelchairDrive, StopsWhenCommandsStopForLongerThanTheTimeout) {
  ASSERT_DOUBLE_EQ(drive_->config().command_timeout, 0.5);
  ASSERT_TRUE(drive_->setCommand(0.5, 0, simulation_.time()));
  for (int i = 0; i < 3000; ++i) simulation_.step();  // 3 s with one command
  const double x = travelled().x;
  EXPECT_GT(x, 0.1);
  EXPECT_LT(x, 0.5 * 0.5 + 0.05) << "moves for about the 0.5 s timeout, then stops";
  EXPECT_LT(std::abs(drive_->odometry().linear_velocity.x()), 0.01);
}

TEST_P(WheelchairDrive, IgnoresNonFiniteCommands) {
  EXPECT_FALSE(drive_->setCommand(NAN, 0, 0));
  EXPECT_FALSE(drive_->setCommand(0, INFINITY, 0));
  for (int i = 0; i < 500; ++i) simulation_.step();
  EXPECT_LT(std::hypot(travelled().x, travelled().y), 0.005);
}

INSTANTIATE_TEST_SUITE_P(WheelModels, WheelchairDrive, ::testing::ValuesIn(test::kWheelModels),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(Simulation, SeedStyleReversedWheelAxisIsCompensated) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    const std::string urdf = test::withWheelModel(
        test::replaceAfter(
            test::expandXacro("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro"),
            "<joint name=\"front_right_joint\"", "<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0 -1 0\"/>"),
        wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    std::vector<std::string> warnings;
    Robot& robot = simulation.spawn(
        "chair", parseModel(urdf, "seed-style chair", PackageResolver::fromEnvironment(), &warnings), {},
        &warnings);
    std::string said;
    for (const auto& w : warnings) said += w + "\n";
    EXPECT_THAT(said, HasSubstr("joint [front_right_joint] turns about 0 -1 0"));
    EXPECT_THAT(said, HasSubstr("driven with the opposite sign"));

    const Eigen::Isometry3d start = robot.body().linkPose("base_footprint");
    drive(simulation, *test::pluginsOf<WheeledDrive>(robot).at(0), 0.5, 0, 2.0);
    const Planar actual = travelled(robot, start);
    EXPECT_GT(actual.x, 0.8);
    EXPECT_LT(std::abs(actual.y), 0.02);
    EXPECT_LT(std::abs(actual.yaw), 1 * kDeg);
  }
}

/// Drives straight at v and turns in place at w, on each wheel model.
void checkSkidSteer(ModelSpec (*load)(const std::string&), double v, double w) {
  for (const auto& wheel_model : test::kWheelModels) {
    const ModelSpec model = load(wheel_model);
    SCOPED_TRACE(model.name + " on " + wheel_model + " wheels");
    for (const double turn : {0.0, w}) {
      Simulation simulation(test::shippedWorld("empty.world"));
      Robot& robot = simulation.spawn("car", model, {});
      WheeledDrive& drive_plugin = *test::pluginsOf<WheeledDrive>(robot).at(0);
      const Eigen::Isometry3d start = robot.body().linkPose("base_footprint");
      const double seconds = 3;
      drive(simulation, drive_plugin, turn == 0 ? v : 0, turn, seconds);
      const Planar actual = travelled(robot, start);
      if (turn == 0) {
        // Straight within 2 %: of the distance commanded, and sideways relative to the distance covered.
        EXPECT_NEAR(actual.x, v * seconds, 0.02 * v * seconds);
        EXPECT_LT(std::abs(actual.y), 0.02 * actual.x);
        continue;
      }
      EXPECT_GT(actual.yaw, 0.05) << "+angular.z turns counter-clockwise";
      if (wheel_model != "raycast") continue;  // Bullet's contact friction is no friction circle (docs/known_limitations.md)
      // Turning in place, four wheels at (+-a, +-b) slide sideways: Coulomb friction balances the yaw moments
      // at w * b^2 / (a^2 + b^2). Within 15 %: the wheels need a moment to spin up.
      const auto poses = linkPosesAtZero(model);
      double a = 0, b = 0;
      const auto& joints = drive_plugin.config().left_joints;
      for (const auto& name : joints) {
        const Eigen::Vector3d at = poses.at(model.joint(name)->child).translation();
        a += std::abs(at.x()) / joints.size();
        b += std::abs(at.y()) / joints.size();
      }
      const double coulomb = w * b * b / (a * a + b * b);
      EXPECT_NEAR(actual.yaw / seconds, coulomb, 0.15 * coulomb);
    }
  }
}

TEST(Simulation, SmartcarGoesStraightAndTurnsTheRightWay) { checkSkidSteer(&test::smartcar, 0.5, 0.5); }

TEST(Simulation, YahboomcarGoesStraightAndTurnsTheRightWay) { checkSkidSteer(&test::yahboomcar, 0.3, 1.0); }

TEST(Simulation, PanTiltHoldsItsPositionAgainstGravity) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("car", test::yahboomcar(wheel_model), {});
    auto* pan_tilt = test::pluginsOf<JointPosition>(robot).at(0);
    for (int i = 0; i < 1000; ++i) simulation.step();
    EXPECT_NEAR(robot.body().jointPosition(robot.body().jointIndex("jq2_Joint")), 0, 0.01);
    ASSERT_TRUE(pan_tilt->setTarget("jq1_Joint", 0.5));
    for (int i = 0; i < 2000; ++i) simulation.step();
    EXPECT_NEAR(robot.body().jointPosition(robot.body().jointIndex("jq1_Joint")), 0.5, 0.01);
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

TEST(Simulation, PanTiltHoldsWhereItSpawns) {
  for (const auto& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    SpawnPose pose;
    pose.joints = {{"jq1_Joint", 0.3}};
    Robot& robot = simulation.spawn("car", test::yahboomcar(wheel_model), pose);
    for (int i = 0; i < 1000; ++i) simulation.step();
    EXPECT_NEAR(robot.body().jointPosition(robot.body().jointIndex("jq1_Joint")), 0.3, 0.01);
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

}  // namespace
}  // namespace bullet_sim

namespace bullet_sim {
namespace {

/// two_wheeler.urdf with a diff drive that publishes its wheels' tf.
std::string twoWheelerWithWheelTf() { return test::twoWheelerWithDiffDrive({{"publishWheelTF", "true"}}); }

TEST(Simulation, PublishWheelTfGivesEachWheelInItsParentAtItsJointAngle) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", test::parseQuietly(twoWheelerWithWheelTf(), "two_wheeler"), {});
  WheeledDrive& drive = *test::pluginsOf<WheeledDrive>(robot).at(0);
  const Stream<TransformSample>* wheel_tf = nullptr;
  for (const auto& port : drive.ports().outputs) {
    const auto* stream = std::get_if<const Stream<TransformSample>*>(&port.stream);
    if (stream && (*stream)->latest().frames.empty())
      wheel_tf = *stream;  // the odom tf has its frame already
  }
  ASSERT_NE(wheel_tf, nullptr);
  ASSERT_TRUE(drive.setCommand(0.2, 0, simulation.time()));
  for (int i = 0; i < 500; ++i) simulation.step();
  ASSERT_EQ(wheel_tf->latest().frames.size(), 2u);
  for (const auto& frame : wheel_tf->latest().frames) {
    SCOPED_TRACE(frame.child);
    EXPECT_EQ(frame.parent, "base_link");
    const double side = frame.child == "left_wheel" ? 1 : -1;
    EXPECT_TRUE(frame.pose.translation().isApprox(Eigen::Vector3d(0.1, side * 0.175, 0), 1e-6));
    const double angle = robot.body().jointPosition(robot.body().jointIndex(frame.child + "_joint"));
    EXPECT_GT(std::abs(angle), 1.0);  // it rolled about 0.1 m on a 0.05 m radius
    const Eigen::AngleAxisd turned(frame.pose.linear());
    EXPECT_NEAR(std::remainder(turned.angle() * turned.axis().y() - angle, 2 * M_PI), 0, 1e-6);
  }
}

}  // namespace
}  // namespace bullet_sim
