// The diff drive and the skid steer against closed forms: the wheelchair's drive axle follows the unicycle
// the ramped command integrates, straight, in place and on arcs; a reversed wheel axis is compensated; the
// cars go straight and turn the right way (at Coulomb's rate on raycast wheels); the wheels' tf. Stepped
// in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/simulation/simulation.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "test/test_support.h"

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
  test::stepSending(simulation, seconds, [&] { return drive.setCommand(v, w, simulation.time()); });
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
  const Odometry& odometry = test::latestOf<Odometry>(*drive_);
  EXPECT_EQ(test::countOf<Odometry>(*drive_), 100u);  // 100 Hz for 1 s
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
  EXPECT_LT(std::abs(test::latestOf<Odometry>(*drive_).linear_velocity.x()), 0.01);
}

// The timeout counts to the start of the step a command drives: under steps longer than the timeout (0.6 s
// against the wheelchair's 0.5 s, which set_physics_properties takes), a command sent before each step drives
// it, at 0.3 m/s once its wheels have ramped up (1.8 m/s^2).
TEST_P(WheelchairDrive, DrivesUnderStepsLongerThanItsCommandTimeout) {
  ASSERT_DOUBLE_EQ(drive_->config().command_timeout, 0.5);
  simulation_.setStepSize(0.6);
  const double start = simulation_.time();
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(drive_->setCommand(0.3, 0, simulation_.time()));
    simulation_.step();
  }
  EXPECT_NEAR(travelled().x, 0.3 * (simulation_.time() - start), 0.1);
}

TEST_P(WheelchairDrive, IgnoresNonFiniteCommands) {
  EXPECT_FALSE(drive_->setCommand(NAN, 0, 0));
  EXPECT_FALSE(drive_->setCommand(0, INFINITY, 0));
  for (int i = 0; i < 500; ++i) simulation_.step();
  EXPECT_LT(std::hypot(travelled().x, travelled().y), 0.005);
}

INSTANTIATE_TEST_SUITE_P(WheelModels, WheelchairDrive, ::testing::ValuesIn(test::kWheelModels),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(DiffDrive, SeedStyleReversedWheelAxisIsCompensated) {
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
      if (wheel_model != "raycast")
        continue;  // Bullet's contact friction is no friction circle (docs/known_limitations.md)
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

TEST(SkidSteer, SmartcarGoesStraightAndTurnsTheRightWay) { checkSkidSteer(&test::smartcar, 0.5, 0.5); }

TEST(SkidSteer, YahboomcarGoesStraightAndTurnsTheRightWay) { checkSkidSteer(&test::yahboomcar, 0.3, 1.0); }

/// two_wheeler.urdf with a diff drive that publishes its wheels' tf.
std::string twoWheelerWithWheelTf() { return test::twoWheelerWithDiffDrive({{"publishWheelTF", "true"}}); }

TEST(DiffDrive, PublishWheelTfGivesEachWheelInItsParentAtItsJointAngle) {
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
