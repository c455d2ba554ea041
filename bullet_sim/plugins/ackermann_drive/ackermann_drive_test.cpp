// The Ackermann drive: its steering geometry as a pure function, and the Tianracer driven in empty.world
// against the bicycle model (circles of radius v / w, steering angles, limits). Stepped in-process, no
// roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <tuple>

#include "plugins/ackermann_drive/ackermann_drive.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kDeg = M_PI / 180;

std::string tianracerUrdf() {
  return test::expandXacro("tianracer_description", "urdf/tianracer.urdf.xacro");
}

/// The Tianracer with its drive asking for `wheel_model`.
ModelSpec tianracer(const std::string& wheel_model) {
  return test::parseQuietly(test::withWheelModel(tianracerUrdf(), wheel_model),
                            "tianracer on " + wheel_model);
}

/// The Tianracer with tags of its drive plugin set.
std::string tianracerWith(const test::Tags& tags) {
  return test::withPluginTags(tianracerUrdf(), "ackermann_drive.so", tags);
}

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); }

TEST(AckermannAngles, AxleLinesMeetAtTheTurnCentre) {
  const double wheelbase = 0.26, track = 0.14;
  for (const double radius : {1.0, -1.0, 0.5, -3.0}) {
    SCOPED_TRACE(radius);
    const SteeringAngles angles = ackermannAngles(wheelbase, track, 1 / radius);
    // The wheel on the inside of the turn steers further: tan = L / (R - T/2) inside, L / (R + T/2) outside.
    const double inner = std::atan(wheelbase / (std::abs(radius) - track / 2));
    const double outer = std::atan(wheelbase / (std::abs(radius) + track / 2));
    EXPECT_NEAR(radius > 0 ? angles.left : -angles.right, inner, 1e-12);
    EXPECT_NEAR(radius > 0 ? angles.right : -angles.left, outer, 1e-12);
    // Each front wheel's axle line, from its steering axis at (L, y), crosses the rear axle line at y = R.
    for (const auto& [y, angle] : {std::pair{track / 2, angles.left}, std::pair{-track / 2, angles.right}}) {
      EXPECT_NEAR(y + wheelbase / std::tan(angle), radius, 1e-12);
    }
  }
  const SteeringAngles straight = ackermannAngles(wheelbase, track, 0);
  EXPECT_EQ(straight.left, 0);
  EXPECT_EQ(straight.right, 0);
}

/// The Tianracer spawned in empty.world, on one wheel model.
class TianracerDrive : public ::testing::Test {
 protected:
  void spawn(const std::string& wheel_model) {
    SpawnPose pose;
    pose.x = 1;
    pose.y = -2;
    pose.yaw = 0.7;
    robot_ = &simulation_.spawn("tianracer", tianracer(wheel_model), pose);
    drive_ = test::pluginsOf<AckermannDrive>(*robot_).at(0);
  }

  /// Runs `seconds` of sim time, re-sending (v, w) every 0.1 s as `rostopic pub -r 10` does; `each_step` sees
  /// the robot after every step.
  template <class Observer>
  void drive(double v, double w, double seconds, Observer each_step) {
    const auto steps = std::lround(seconds / simulation_.stepSize());
    const auto resend = std::lround(0.1 / simulation_.stepSize());
    for (long i = 0; i < steps; ++i) {
      if (i % resend == 0) {
        ASSERT_TRUE(drive_->setCommand(v, w, simulation_.time()));
      }
      simulation_.step();
      each_step();
    }
  }
  void drive(double v, double w, double seconds) {
    drive(v, w, seconds, [] {});
  }

  /// The midpoint of the rear axle on the ground plane, in the world: the point the bicycle model turns.
  Eigen::Vector2d rearAxle() const {
    const Eigen::Vector3d left = robot_->body().linkPose("left_rear_wheel").translation();
    const Eigen::Vector3d right = robot_->body().linkPose("right_rear_wheel").translation();
    return ((left + right) / 2).head<2>();
  }
  double jointAngle(const std::string& joint) const {
    return robot_->body().jointPosition(robot_->body().jointIndex(joint));
  }

  Simulation simulation_{test::shippedWorld("empty.world")};
  Robot* robot_ = nullptr;
  AckermannDrive* drive_ = nullptr;
};

/// Behaviour tests run against every wheel model.
class Tianracer : public TianracerDrive, public ::testing::WithParamInterface<std::string> {
 protected:
  void SetUp() override { spawn(GetParam()); }
};

INSTANTIATE_TEST_SUITE_P(WheelModels, Tianracer, ::testing::ValuesIn(test::kWheelModels),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST_P(Tianracer, RestsOnTheGroundWhereItSpawns) {
  const Eigen::Isometry3d start = robot_->body().linkPose("base_link");
  drive(0, 0, 2.0);
  const Eigen::Isometry3d end = robot_->body().linkPose("base_link");
  EXPECT_NEAR(end.translation().z(), start.translation().z(), 0.001);
  const Eigen::Vector3d up = end.linear().col(2);
  EXPECT_LT(std::acos(std::min(1.0, up.z())), 0.5 * kDeg) << "roll or pitch";
  EXPECT_NEAR(end.translation().x(), 1, 0.005);
  EXPECT_NEAR(end.translation().y(), -2, 0.005);
  EXPECT_NEAR(jointAngle("left_steering_hinge_joint"), 0, 0.001)
      << "w = 0 and v = 0 keep the wheels straight";
  EXPECT_NEAR(jointAngle("right_steering_hinge_joint"), 0, 0.001);
}

TEST_P(Tianracer, GeometryComesFromTheUrdf) {
  // The seed's hinge joints at y = +-0.070647 m, the wheels 0.015649 m further out; our 0.26 m wheelbase;
  // the wheel radius of the seed's wheel inertia.
  const AckermannGeometry& geometry = drive_->geometry();
  EXPECT_NEAR(geometry.wheelbase, 0.26, 1e-9);
  EXPECT_NEAR(geometry.steering_track, 2 * 0.070647, 1e-9);
  EXPECT_NEAR(geometry.rear_track, 2 * (0.070647 + 0.015649), 1e-9);
  EXPECT_NEAR(geometry.wheel_radius, std::sqrt(2 * 0.00041226 / 0.7), 1e-9);
}

struct Circle {
  double v, w;  ///< [m/s], [rad/s]
};

class TianracerCircle : public TianracerDrive,
                        public ::testing::WithParamInterface<std::tuple<std::string, Circle>> {
 protected:
  void SetUp() override { spawn(std::get<0>(GetParam())); }
};

TEST_P(TianracerCircle, DrivesACircleOfRadiusVOverW) {
  const auto [v, w] = std::get<1>(GetParam());
  drive(v, w, 2.0);             // the steering settles and the car gets up to speed
  double path = 0, turned = 0;  // [m], [rad]
  Eigen::Vector2d last = rearAxle();
  double last_yaw = yawOf(robot_->body().linkPose("base_footprint"));
  drive(v, w, 6.0, [&] {
    const Eigen::Vector2d now = rearAxle();
    const double yaw = yawOf(robot_->body().linkPose("base_footprint"));
    path += (now - last).norm();
    turned += std::remainder(yaw - last_yaw, 2 * M_PI);
    last = now;
    last_yaw = yaw;
  });
  EXPECT_GT(turned * w, 0) << "+w turns counter-clockwise, -w clockwise, in either direction of travel";
  const double radius = path / std::abs(turned);
  const double expected = std::abs(v / w);
  EXPECT_NEAR(radius, expected, 0.05 * expected);
  std::printf("[ measured ] %s, v %.2f w %.2f: radius %.4f m for %.4f m (%+.2f %%)\n",
              std::get<0>(GetParam()).c_str(), v, w, radius, expected, 100 * (radius - expected) / expected);
}

INSTANTIATE_TEST_SUITE_P(Commands, TianracerCircle,
                         ::testing::Combine(::testing::ValuesIn(test::kWheelModels),
                                            ::testing::Values(Circle{0.5, 0.5}, Circle{0.8, -0.4},
                                                              Circle{-0.5, 0.5})),
                         [](const ::testing::TestParamInfo<std::tuple<std::string, Circle>>& info) {
                           const Circle& circle = std::get<1>(info.param);
                           return std::get<0>(info.param) + (circle.v > 0 ? "_forward" : "_reverse") +
                                  (circle.w > 0 ? "_left" : "_right");
                         });

TEST_P(Tianracer, SteeringJointsReachTheirAckermannAngles) {
  drive(0.5, 0.5, 1.0);
  const AckermannGeometry& geometry = drive_->geometry();
  const SteeringAngles expected = ackermannAngles(geometry.wheelbase, geometry.steering_track, 1.0);
  EXPECT_NEAR(drive_->curvature(), 1.0, 1e-12);
  EXPECT_NEAR(jointAngle("left_steering_hinge_joint"), expected.left, 0.2 * kDeg);
  EXPECT_NEAR(jointAngle("right_steering_hinge_joint"), expected.right, 0.2 * kDeg);
  EXPECT_GT(expected.left, expected.right) << "the inner wheel steers further";
}

TEST_P(Tianracer, CommandsBeyondMaxSteerAreClamped) {
  const double max_steer = drive_->config().max_steer;
  ASSERT_DOUBLE_EQ(max_steer, 0.6);
  for (const double w : {5.0, -5.0}) {
    SCOPED_TRACE(w);
    drive(0.5, w, 1.0);  // a radius of 0.1 m, tighter than the car can steer
    const double inner = jointAngle(w > 0 ? "left_steering_hinge_joint" : "right_steering_hinge_joint");
    const double outer = jointAngle(w > 0 ? "right_steering_hinge_joint" : "left_steering_hinge_joint");
    EXPECT_NEAR(std::abs(inner), max_steer, 0.2 * kDeg) << "the inner wheel stops at max_steer";
    const AckermannGeometry& geometry = drive_->geometry();
    const SteeringAngles expected =
        ackermannAngles(geometry.wheelbase, geometry.steering_track, drive_->curvature());
    EXPECT_NEAR(outer, w > 0 ? expected.right : expected.left, 0.2 * kDeg)
        << "the outer one follows Ackermann";
    EXPECT_LT(std::abs(outer), std::abs(inner));
    EXPECT_LT(std::abs(drive_->curvature()), 10.0);
  }
}

TEST_P(Tianracer, TurnAtStandstillSteersButDoesNotMove) {
  const Eigen::Vector2d start = rearAxle();
  drive(0, 0.5, 1.0);
  EXPECT_NEAR(jointAngle("left_steering_hinge_joint"), drive_->config().max_steer, 0.2 * kDeg);
  EXPECT_LT((rearAxle() - start).norm(), 0.005);
  drive(0, 0, 1.0);
  EXPECT_NEAR(jointAngle("left_steering_hinge_joint"), 0, 0.2 * kDeg) << "v = w = 0 steers straight again";
  EXPECT_NEAR(jointAngle("right_steering_hinge_joint"), 0, 0.2 * kDeg);
  EXPECT_LT((rearAxle() - start).norm(), 0.005);
}

TEST_P(Tianracer, DrivesStraightAndPublishesOdometry) {
  const Eigen::Vector2d start = rearAxle();
  const double yaw = yawOf(robot_->body().linkPose("base_footprint"));
  drive(0.5, 0, 3.0);
  const Eigen::Vector2d moved = rearAxle() - start;
  const Eigen::Vector2d heading(std::cos(yaw), std::sin(yaw));
  EXPECT_NEAR(moved.dot(heading), 1.5, 0.05) << "0.5 m/s for 3 s, less the spin-up";
  EXPECT_LT(std::abs(moved.x() * heading.y() - moved.y() * heading.x()), 0.02 * 1.5) << "sideways";
  EXPECT_EQ(test::countOf<Odometry>(*drive_), 300u);  // 100 Hz for 3 s
  const Odometry& odometry = test::latestOf<Odometry>(*drive_);
  EXPECT_DOUBLE_EQ(odometry.stamp, simulation_.time());
  EXPECT_TRUE(odometry.pose.isApprox(robot_->body().linkPose("base_footprint"), 1e-12));
  EXPECT_NEAR(odometry.linear_velocity.x(), 0.5, 0.02);
  EXPECT_TRUE(drive_->config().publish_odometry);
  EXPECT_TRUE(drive_->config().publish_odom_tf);
}

TEST_P(Tianracer, IgnoresNonFiniteCommands) {
  EXPECT_FALSE(drive_->setCommand(NAN, 0, 0));
  EXPECT_FALSE(drive_->setCommand(0, INFINITY, 0));
  const Eigen::Vector2d start = rearAxle();
  for (int i = 0; i < 500; ++i) simulation_.step();
  EXPECT_LT((rearAxle() - start).norm(), 0.005);
}

/// The problems and warnings of spawning the Tianracer with its plugin block edited.
std::string loadMessages(const std::string& urdf) {
  Simulation simulation(test::shippedWorld("empty.world"));
  std::vector<std::string> warnings;
  std::string said;
  try {
    simulation.spawn("car",
                     parseModel(urdf, "edited tianracer", PackageResolver::fromEnvironment(), &warnings), {},
                     &warnings);
  } catch (const SpecError& error) {
    said = error.what();
  }
  for (const auto& warning : warnings) said += "\n" + warning;
  return said;
}

TEST(AckermannConfig, AJointTypoIsAnErrorWithASuggestion) {
  const std::string said = loadMessages(tianracerWith({{"rear_left_joint", "left_rear_wheel_jiont"}}));
  EXPECT_THAT(said,
              HasSubstr("plugin [ackermann_drive] <rear_left_joint> [left_rear_wheel_jiont] is not a joint "
                        "(did you mean [left_rear_wheel_joint]?)"));
}

TEST(AckermannConfig, GainsAreReadAndIgnoredWithOneWarning) {
  const std::string said = loadMessages(tianracerWith({{"left_steering_pid_gain", "1500 0 1"},
                                                       {"right_steering_pid_gain", "1500 0 1"},
                                                       {"linear_velocity_pid_gain", "1000 0 1"}}));
  EXPECT_THAT(said, HasSubstr("plugin [ackermann_drive] <left_steering_pid_gain>, <right_steering_pid_gain>, "
                              "<linear_velocity_pid_gain>: read and ignored"));
  EXPECT_THAT(said, Not(HasSubstr("is not a tag this plugin knows")));
}

TEST(AckermannConfig, FiguresThatDisagreeWithTheUrdfAreReported) {
  const std::string said = loadMessages(tianracerWith({{"wheel_base", "10.26"}}));
  EXPECT_THAT(said, HasSubstr("plugin [ackermann_drive] <wheel_base> 10.26 m disagrees with the URDF"));
}

TEST(AckermannConfig, UnknownTagsGetOneWarning) {
  const std::string said = loadMessages(tianracerWith({{"max_sped", "3"}}));
  EXPECT_THAT(said, HasSubstr("plugin [ackermann_drive] <max_sped> is not a tag this plugin knows: ignored"));
}

TEST(AckermannConfig, TheWheelModelIsContactOrRaycast) {
  for (const std::string model : {"contact", "raycast", "magic"}) {
    SCOPED_TRACE(model);
    const std::string said = loadMessages(tianracerWith({{"wheelModel", model}}));
    if (model == "magic") {
      EXPECT_THAT(said,
                  HasSubstr("plugin [ackermann_drive] <wheelModel> must be contact or raycast, not [magic]"));
    } else {
      EXPECT_EQ(said, "");
    }
  }
}

TEST(AckermannConfig, TheShippedTianracerLoadsWithoutWarnings) {
  EXPECT_EQ(loadMessages(tianracerUrdf()), "");
}

}  // namespace
}  // namespace bullet_sim
