// diff_drive_controller's odometry, speed limiter and command path against closed forms: no physics, a body
// whose joints turn exactly as commanded.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/plugins/registry.h"
#include "plugins/ros_control/diff_drive_controller.h"
#include "plugins/ros_control/controller_manager.h"
#include "plugins/ros_control/controller_registry.h"
#include "plugins/ros_control/diff_drive_odometry.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

constexpr double kDt = 0.01;  // [s] the control period of these tests

TEST(DiffDriveOdometry, FollowsAnArcExactly) {
  // Wheels of r = 0.1 m, 0.5 m apart, turning at constant rates: the base moves on a circle of radius
  // R = (vr + vl) / 2 / w with w = (vr - vl) / separation.
  DiffDriveOdometry odometry(1);
  odometry.setWheelParams(0.5, 0.1, 0.1);
  odometry.init(0);
  const double left_rate = 4.0, right_rate = 6.0;  // [rad/s]
  const double v = 0.1 * (left_rate + right_rate) / 2, w = 0.1 * (right_rate - left_rate) / 0.5;
  odometry.update(0, 0, 0);
  for (int k = 1; k <= 300; ++k) odometry.update(left_rate * k * kDt, right_rate * k * kDt, k * kDt);
  const double t = 300 * kDt, radius = v / w;
  EXPECT_NEAR(odometry.heading(), w * t, 1e-12);
  EXPECT_NEAR(odometry.x(), radius * std::sin(w * t), 1e-12);
  EXPECT_NEAR(odometry.y(), radius * (1 - std::cos(w * t)), 1e-12);
  EXPECT_NEAR(odometry.linear(), v, 1e-9);
  EXPECT_NEAR(odometry.angular(), w, 1e-9);
}

TEST(DiffDriveOdometry, GoesStraightAndTurnsInPlace) {
  DiffDriveOdometry odometry(1);
  odometry.setWheelParams(0.5, 0.1, 0.1);
  odometry.update(0, 0, 0);
  odometry.update(10, 10, 1);  // 1 m straight ahead
  EXPECT_NEAR(odometry.x(), 1.0, 1e-12);
  EXPECT_NEAR(odometry.y(), 0.0, 1e-12);
  odometry.update(10 - 1.25 * M_PI, 10 + 1.25 * M_PI, 2);  // each rim pi / 8 m: a quarter turn in place
  EXPECT_NEAR(odometry.heading(), M_PI / 2, 1e-12);
  EXPECT_NEAR(odometry.x(), 1.0, 1e-12);
  EXPECT_NEAR(odometry.y(), 0.0, 1e-12);
}

TEST(DiffDriveOdometry, VelocitiesAreRollingMeansOverTheWindow) {
  DiffDriveOdometry odometry(3);
  odometry.setWheelParams(0.5, 0.1, 0.1);
  odometry.update(0, 0, 0);
  // Straight on, at 1, 2, 3 and then 6 rad/s: the mean of the last three speeds.
  double position = 0;
  int k = 0;
  for (double rate : {1.0, 2.0, 3.0, 6.0}) {
    position += rate * kDt;
    odometry.update(position, position, ++k * kDt);
  }
  EXPECT_NEAR(odometry.linear(), 0.1 * (2 + 3 + 6) / 3, 1e-9);
}

TEST(DiffDriveOdometry, AMillionSampleWindowAveragesEverySampleInIt) {
  DiffDriveOdometry odometry(1000000);
  odometry.setWheelParams(0.5, 0.1, 0.1);
  odometry.update(0, 0, 0);
  // 60,000 updates at 1 rad/s, then 40,000 at 3 rad/s: all within the window.
  double position = 0;
  for (int k = 1; k <= 100000; ++k) {
    position += (k <= 60000 ? 1.0 : 3.0) * kDt;
    odometry.update(position, position, k * kDt);
  }
  EXPECT_NEAR(odometry.linear(), 0.1 * (0.6 * 1.0 + 0.4 * 3.0), 1e-9);
}

TEST(SpeedLimiter, ClipsVelocityThenAcceleration) {
  SpeedLimiter limiter;
  limiter.has_velocity_limits = limiter.has_acceleration_limits = true;
  limiter.max_velocity = 1.0;
  limiter.min_velocity = -0.5;
  limiter.max_acceleration = 3.0;
  limiter.min_acceleration = -3.0;
  // From rest, a step to 2 m/s climbs at 3 m/s^2 and stops at 1 m/s: v_k = min(1, 3 k dt).
  double v0 = 0, v1 = 0;
  for (int k = 1; k <= 50; ++k) {
    const double v = limiter.limit(2.0, v0, v1, kDt);
    EXPECT_NEAR(v, std::min(1.0, 3.0 * k * kDt), 1e-12) << "update " << k;
    v1 = v0;
    v0 = v;
  }
  EXPECT_NEAR(limiter.limit(-2.0, 0, 0, 1.0), -0.5, 1e-12);  // min_velocity
}

TEST(SpeedLimiter, ClipsJerk) {
  SpeedLimiter limiter;
  limiter.has_jerk_limits = true;
  limiter.max_jerk = 10.0;
  limiter.min_jerk = -10.0;
  // From rest, the acceleration grows by at most 2 j dt per update: v_k = j dt^2 k (k + 1).
  double v0 = 0, v1 = 0;
  for (int k = 1; k <= 20; ++k) {
    const double v = limiter.limit(100.0, v0, v1, kDt);
    EXPECT_NEAR(v, 10.0 * kDt * kDt * k * (k + 1), 1e-12) << "update " << k;
    v1 = v0;
    v0 = v;
  }
}

TEST(SpeedLimiter, ReadsRosControllersNamesWithMinimaDefaultingToMinusMaxima) {
  const ParameterTree parameters = ParameterTree::fromYaml(
      "has_velocity_limits: true\nmax_velocity: 2.0\nhas_acceleration_limits: true\nmax_acceleration: 4.0\n"
      "min_acceleration: -1.0\n",
      "limits");
  const SpeedLimiter limiter = SpeedLimiter::fromParameters(parameters);
  EXPECT_TRUE(limiter.has_velocity_limits);
  EXPECT_DOUBLE_EQ(limiter.min_velocity, -2.0);
  EXPECT_DOUBLE_EQ(limiter.max_acceleration, 4.0);
  EXPECT_DOUBLE_EQ(limiter.min_acceleration, -1.0);
  EXPECT_FALSE(limiter.has_jerk_limits);
}

/// A robot whose joints move exactly as commanded: velocity and effort commands set the speed, position
/// commands the position. No physics, so what a controller computes is all there is.
class IdealBody : public RobotBody {
 public:
  explicit IdealBody(ModelSpec spec) : spec_(std::move(spec)) {
    for (const auto& joint : spec_.joints) {
      if (joint.moves()) names_.push_back(joint.name);
    }
    positions_.assign(names_.size(), 0.0);
    velocities_.assign(names_.size(), 0.0);
  }
  void step(double dt) {
    for (size_t j = 0; j < names_.size(); ++j) positions_[j] += velocities_[j] * dt;
  }

  const ModelSpec& spec() const override { return spec_; }
  int jointIndex(const std::string& joint) const override {
    const auto found = std::find(names_.begin(), names_.end(), joint);
    return found == names_.end() ? -1 : static_cast<int>(found - names_.begin());
  }
  double jointPosition(int joint) const override { return positions_.at(joint); }
  double jointVelocity(int joint) const override { return velocities_.at(joint); }
  double jointEffort(int) const override { return 0; }
  void setJointVelocity(int joint, double velocity, double) override { velocities_.at(joint) = velocity; }
  void setJointPosition(int joint, double position, double) override { positions_.at(joint) = position; }
  void setJointEffort(int joint, double effort) override { velocities_.at(joint) = effort; }
  void setRootVelocity(const Eigen::Vector3d&, const Eigen::Vector3d&) override {}
  void applyLinkWrench(const std::string&, const Eigen::Vector3d&, const Eigen::Vector3d&) override {}
  bool takesJointEffort(int) const override { return false; }
  void applyJointEffort(int, double) override {}
  std::vector<CollisionContact> contacts(const CollisionSource&) const override { return {}; }
  Eigen::Isometry3d linkPose(const std::string&) const override { return Eigen::Isometry3d::Identity(); }
  Eigen::Vector3d linkLinearVelocity(const std::string&) const override { return Eigen::Vector3d::Zero(); }
  Eigen::Vector3d linkAngularVelocity(const std::string&) const override { return Eigen::Vector3d::Zero(); }
  const std::vector<RobotPart>& parts() const override { return parts_; }
  int partOf(const std::string&) const override { return -1; }
  Eigen::Isometry3d partPose(int) const override { return Eigen::Isometry3d::Identity(); }

 private:
  ModelSpec spec_;
  std::vector<std::string> names_;
  std::vector<double> positions_, velocities_;
  std::vector<RobotPart> parts_;
};

/// The rover (rover_description) with its control.yaml and `extra` YAML over it, on an ideal body, its diff
/// drive controller loaded and started: what ros_control's plugin does each control period, by hand.
class RoverController : public ::testing::Test {
 protected:
  void SetUp() override { build(""); }

  void build(const std::string& extra) {
    const std::string yaml = test::readFile(test::packageFile("rover_description", "config/control.yaml"));
    parameters_ = std::make_unique<TreeParameters>(ParameterTree::fromYaml(yaml + extra, "control.yaml"));
    body_ = std::make_unique<IdealBody>(
        test::parseQuietly(test::expandXacro("rover_description", "urdf/rover.urdf.xacro"), "rover"));
    std::vector<DrivenJoint> joints;
    for (const auto& transmission : body_->spec().transmissions)
      joints.push_back({transmission.joints.front().name, JointInterface::kVelocity});
    hardware_ = std::make_unique<RobotHardware>(joints, *body_, ParameterTree(), nullptr);
    manager_ = std::make_unique<ControllerManager>(*hardware_, ControllerRegistry::builtin(),
                                                   parameters_.get(), "/", body_->spec());
    test::startControllers(*manager_, {kName}, 0);
    controller_ = dynamic_cast<DiffDriveController*>(manager_->find(kName));
    ASSERT_NE(controller_, nullptr);
  }

  /// The controller's input or output port on `topic`.
  const InputPort& input(const std::string& topic) const {
    for (const auto& port : controller_->ports().inputs) {
      if (port.topic == topic) return port;
    }
    throw std::runtime_error("no input " + topic);
  }
  std::string command(double linear, double angular) {
    Twist twist;
    twist.linear.x() = linear;
    twist.angular.z() = angular;
    return std::get<InputHandler<Twist>>(input(std::string(kName) + "/cmd_vel").sink)(twist, time_);
  }
  /// One control period: read the joints, update the controller, drive the joints, move them.
  void update() {
    time_ += kDt;
    hardware_->read(*body_);
    manager_->update(time_, kDt, false);
    hardware_->write(*body_, kDt, false);
    body_->step(kDt);
  }
  double wheelCommand(const std::string& joint) { return hardware_->find(joint)->command; }

  static constexpr const char* kName = "rover_velocity_controller";
  std::unique_ptr<TreeParameters> parameters_;
  std::unique_ptr<IdealBody> body_;
  std::unique_ptr<RobotHardware> hardware_;
  std::unique_ptr<ControllerManager> manager_;
  DiffDriveController* controller_ = nullptr;
  double time_ = 0;
};

TEST_F(RoverController, ReadsTheWheelGeometryFromTheUrdf) {
  EXPECT_NEAR(controller_->wheelSeparation(), 0.56, 1e-12);  // the first left and right wheels' joints
  EXPECT_NEAR(controller_->wheelRadius(), 0.165, 1e-12);     // the first left wheel's collision cylinder
}

TEST_F(RoverController, OdometryOfIdealWheelsIsTheUnicycleOfTheLimitedCommand) {
  // v 0.5 m/s and w 0.3 rad/s ramp up at 3 m/s^2 and 6 rad/s^2 (control.yaml's limits). The wheels turn
  // exactly as commanded, one period later, so the odometry integrates the limited commands exactly.
  double x = 0, y = 0, heading = 0, v = 0, w = 0;
  for (int k = 1; k <= 600; ++k) {
    if (k % 10 == 1) {
      ASSERT_EQ(command(0.5, 0.3), "");  // well within the 0.25 s cmd_vel_timeout
    }
    update();
    if (std::abs(w) > 1e-6) {  // the pose moves with the command of the update before
      x += v / w * (std::sin(heading + w * kDt) - std::sin(heading));
      y -= v / w * (std::cos(heading + w * kDt) - std::cos(heading));
    } else {
      x += v * kDt * std::cos(heading);
      y += v * kDt * std::sin(heading);
    }
    heading += w * kDt;
    v = std::min(0.5, 3.0 * k * kDt);
    w = std::min(0.3, 6.0 * k * kDt);
  }
  const DiffDriveOdometry& odometry = controller_->odometry();
  EXPECT_NEAR(odometry.heading(), heading, 1e-9);
  EXPECT_NEAR(odometry.x(), x, 1e-9);
  EXPECT_NEAR(odometry.y(), y, 1e-9);
  EXPECT_NEAR(odometry.linear(), 0.5, 1e-9);
  EXPECT_NEAR(odometry.angular(), 0.3, 1e-9);
  // Each side's wheels at (v -/+ w * 1.875 * 0.56 / 2) / 0.165.
  EXPECT_NEAR(wheelCommand("front_left_wheel"), (0.5 - 0.3 * 1.875 * 0.28) / 0.165, 1e-9);
  EXPECT_NEAR(wheelCommand("rear_right_wheel"), (0.5 + 0.3 * 1.875 * 0.28) / 0.165, 1e-9);
}

TEST_F(RoverController, LimitsClipTheCommandAsRosControllersDo) {
  build("  publish_cmd: true\n");
  const auto& out = *std::get<const Stream<StampedTwist>*>(controller_->ports().outputs.back().stream);
  ASSERT_EQ(controller_->ports().outputs.back().topic, std::string(kName) + "/cmd_vel_out");
  // A step to 2 m/s and 3 rad/s, above the 1 m/s and 2 rad/s limits:
  // v_k = min(1, 3 k dt), w_k = min(2, 6 k dt).
  for (int k = 1; k <= 50; ++k) {
    ASSERT_EQ(command(2.0, 3.0), "");
    update();
    EXPECT_NEAR(out.latest().twist.linear.x(), std::min(1.0, 3.0 * k * kDt), 1e-12) << "update " << k;
    EXPECT_NEAR(out.latest().twist.angular.z(), std::min(2.0, 6.0 * k * kDt), 1e-12) << "update " << k;
    EXPECT_NEAR(out.latest().stamp, k * kDt, 1e-9);
  }
}

TEST_F(RoverController, StopsWhenTheCommandTimesOut) {
  for (int k = 1; k <= 100; ++k) {
    if (k % 10 == 1) {
      ASSERT_EQ(command(0.5, 0.0), "");
    }
    update();
  }
  const double full = 0.5 / 0.165;  // [rad/s]
  EXPECT_NEAR(wheelCommand("front_left_wheel"), full, 1e-9);
  // The last command came at t = 0.90 s: once it is more than cmd_vel_timeout (0.25 s) old the command is 0,
  // which the wheels reach at -3 m/s^2.
  while (wheelCommand("front_left_wheel") > full - 1e-9) update();
  EXPECT_NEAR(time_, 0.90 + 0.25, kDt + 1e-9);
  EXPECT_NEAR(wheelCommand("front_left_wheel"), full - 3.0 * kDt / 0.165, 1e-9);
  for (int k = 0; k < 15; ++k) update();  // 0.47 m/s down to 0.02 m/s
  EXPECT_GT(wheelCommand("front_left_wheel"), 0.0);
  update();
  EXPECT_EQ(wheelCommand("front_left_wheel"), 0.0);
  EXPECT_EQ(wheelCommand("rear_right_wheel"), 0.0);
}

TEST_F(RoverController, RefusesWhatRosControllersRefuse) {
  EXPECT_THAT(command(std::nan(""), 0.1), HasSubstr("not finite"));
  build("  allow_multiple_cmd_vel_publishers: false\n");
  ASSERT_EQ(command(0.5, 0), "");
  update();
  input(std::string(kName) + "/cmd_vel").publishers->count = 2;
  EXPECT_THAT(command(0.5, 0), HasSubstr("from one of 2 publishers"));
  EXPECT_EQ(wheelCommand("front_left_wheel"), 0.0);  // it brakes

  SwitchControllerRequest stop;
  stop.stop = {kName};
  ASSERT_EQ(manager_->switchControllers(stop, time_, nullptr), "");
  EXPECT_THAT(command(0.5, 0), HasSubstr("which is not running"));
}

/// Parameters a controller cannot drive with (NaN would reach the wheels or never time out) are refused as it
/// loads, naming the value, as the other controllers' are.
TEST_F(RoverController, RefusesParametersThatCannotDrive) {
  const std::string drive =
      "  type: diff_drive_controller/DiffDriveController\n"
      "  left_wheel: [front_left_wheel, rear_left_wheel]\n"
      "  right_wheel: [front_right_wheel, rear_right_wheel]\n";
  const std::vector<std::pair<std::string, std::string>> rows = {
      {"wheel_radius: .inf", "radii (inf, inf m), multipliers included, must be finite and > 0"},
      {"wheel_separation_multiplier: .nan", "the wheel separation (nan m)"},
      {"linear: {x: {has_velocity_limits: true, max_velocity: .nan}}",
       "linear/x/max_velocity must be a number, not [.nan]"},
      {"angular: {z: {has_acceleration_limits: true, min_acceleration: .nan}}",
       "angular/z/min_acceleration must be a number, not [.nan]"},
      {"cmd_vel_timeout: .nan", "cmd_vel_timeout must be >= 0 [s], not [.nan]"},
      {"cmd_vel_timeout: -1", "cmd_vel_timeout must be >= 0 [s], not [-1]"},
      {"publish_rate: .inf", "publish_rate must be finite and > 0 [Hz], not [.inf]"},
      {"velocity_rolling_window_size: 1e18",
       "velocity_rolling_window_size must be at most 1000000 samples, not [1e18]"},
      {"velocity_rolling_window_size: .nan",
       "velocity_rolling_window_size must be at most 1000000 samples, not [.nan]"},
  };
  std::string yaml =
      "nan_publisher:\n  type: joint_state_controller/JointStateController\n  publish_rate: .nan\n";
  for (size_t i = 0; i < rows.size(); ++i)
    yaml += "bad_" + std::to_string(i) + ":\n" + drive + "  " + rows[i].first + "\n";
  build(yaml);
  for (size_t i = 0; i < rows.size(); ++i) {
    const std::string name = "bad_" + std::to_string(i);
    EXPECT_THAT(manager_->load(name, nullptr), HasSubstr(rows[i].second)) << rows[i].first;
  }
  EXPECT_THAT(manager_->load("nan_publisher", nullptr),
              HasSubstr("publish_rate must be finite and >= 0 [Hz], not [.nan]"));
}

}  // namespace
}  // namespace bullet_sim
