// Our own robots driven both ways, in-process: the Yahboom pan/tilt through its joint pose plugin and through
// ros_control (yahboomcar.urdf.xacro pan_tilt:=ros_control, config/pan_tilt_control.yaml) reaches the same
// angles, and its camera sees the same image; the Tianracer through its Ackermann plugin and through
// ros_control (tianracer.urdf.xacro drive:=ros_control, config/control.yaml, with the six commands
// ackermann_joint_commander sends) drives the same arc, the bicycle model's.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/ackermann_drive/ackermann_drive.h"
#include "plugins/joint_position/joint_position.h"
#include "plugins/ros_control/joint_trajectory_controller.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/simulation_images.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

constexpr double kPan = 0.6, kTilt = 0.4;  // [rad] where both ways point the camera

/// The Yahboom car with its pan/tilt driven as `pan_tilt` says, in test_room.world, its camera rendered (at
/// 4 Hz rather than 30, to keep the test quick).
class PanTiltCar {
 public:
  explicit PanTiltCar(const std::string& pan_tilt)
      : parameters_(ParameterTree::fromYaml(
            test::readFile(test::packageFile("yahboomcar_description", "config/pan_tilt_control.yaml")),
            "pan_tilt_control.yaml")) {
    SimulationOptions options;
    options.parameters = &parameters_;
    options.images = imagesFrom([this]() -> SceneRenderer& { return renderer_; });
    simulation_ = std::make_unique<Simulation>(test::shippedWorld("test_room.world"), options);
    std::string urdf =
        test::expandXacro("yahboomcar_description", "urdf/yahboomcar.urdf.xacro", {"pan_tilt:=" + pan_tilt});
    urdf = test::replaceAfter(urdf, "<sensor name=\"camera\"", "<update_rate>30", "<update_rate>4");
    robot_ = &simulation_->spawn("car", test::parseQuietly(urdf, "yahboomcar " + pan_tilt), {});
    camera_ = robot_->outputs<CameraImage>().at(0).stream;
  }

  double angle(const std::string& joint) const {
    return robot_->body().jointPosition(robot_->body().jointIndex(joint));
  }
  /// Steps until the camera has rendered one more frame; that frame.
  const CameraImage& nextFrame() {
    const uint64_t target = camera_->count() + 1;
    test::stepUntil(
        *simulation_, [&] { return camera_->count() >= target; }, 1.0, "a camera frame");
    return camera_->latest();
  }
  void stepFor(double seconds) {
    for (long k = std::lround(seconds / simulation_->stepSize()); k > 0; --k) simulation_->step();
  }
  Simulation& simulation() { return *simulation_; }
  Robot& robot() { return *robot_; }

 private:
  TreeParameters parameters_;
  OffscreenRenderer renderer_;
  std::unique_ptr<Simulation> simulation_;
  Robot* robot_ = nullptr;
  const Stream<CameraImage>* camera_ = nullptr;  ///< the camera's colour images
};

/// The mean absolute difference of two images' bytes.
double meanDifference(const CameraImage& a, const CameraImage& b) {
  EXPECT_EQ(a.data.size(), b.data.size());
  double sum = 0;
  for (size_t i = 0; i < a.data.size() && i < b.data.size(); ++i)
    sum += std::abs(int(a.data[i]) - int(b.data[i]));
  return sum / std::max<size_t>(a.data.size(), 1);
}

JointTrajectory panTiltTo(double pan, double tilt, double seconds) {
  JointTrajectory trajectory;
  trajectory.joint_names = {"jq1_Joint", "jq2_Joint"};
  trajectory.points.push_back({{pan, tilt}, {}, {}, {}, seconds});
  return trajectory;
}

TEST(PanTiltBothWays, ThePluginAndRosControlReachTheSameAnglesAndTheCameraTurnsWithThem) {
  PanTiltCar plugin("plugin");
  const CameraImage before = plugin.nextFrame();
  auto& pan_tilt = *test::pluginsOf<JointPosition>(plugin.robot()).at(0);
  const auto& command = std::get<InputHandler<JointTrajectory>>(pan_tilt.ports().inputs.at(0).sink);
  ASSERT_EQ(command(panTiltTo(kPan, kTilt, 0), plugin.simulation().time()), "");
  plugin.stepFor(1.5);

  PanTiltCar controlled("ros_control");
  auto& manager = test::pluginsOf<RosControl>(controlled.robot()).at(0)->controllerManager();
  test::startControllers(manager, {"pan_tilt_controller"}, controlled.simulation().time());
  auto& controller = dynamic_cast<JointTrajectoryController&>(*manager.find("pan_tilt_controller"));
  const auto& action =
      std::get<ActionHandlers<FollowJointTrajectoryAction>>(controller.ports().actions.at(0).sink);
  FollowJointTrajectoryAction::Goal goal;
  goal.trajectory = panTiltTo(kPan, kTilt, 1.0);
  ASSERT_TRUE(action.goal(1, goal, controlled.simulation().time()).accepted);
  controlled.stepFor(1.5);
  const auto reports = action.reports->take();
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.back().end, GoalEnd::kSucceeded);

  for (const auto& [joint, wanted] : {std::pair{"jq1_Joint", kPan}, std::pair{"jq2_Joint", kTilt}}) {
    EXPECT_NEAR(plugin.angle(joint), wanted, 0.01) << joint << " through the plugin";
    EXPECT_NEAR(controlled.angle(joint), plugin.angle(joint), 0.01) << joint << " both ways";
  }
  // The camera rides jq2_Link: turned by the same angles, it sees the same room, and not what it saw at home.
  const Eigen::Isometry3d a = plugin.robot().body().linkPose("jq2_Link");
  const Eigen::Isometry3d b = controlled.robot().body().linkPose("jq2_Link");
  EXPECT_LT(Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle(), 0.02);
  const Eigen::Vector3d view = a.linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(view.y(), view.x()), kPan, 0.02);  // pan about z, then tilt about -y: looking up
  EXPECT_NEAR(std::asin(view.z()), kTilt, 0.02);
  const CameraImage& turned = plugin.nextFrame();
  const double both_ways = meanDifference(turned, controlled.nextFrame());
  const double turning = meanDifference(turned, before);
  EXPECT_LT(both_ways, 2.0);
  EXPECT_GT(turning, 10 * both_ways + 5);
}

/// The Tianracer driven as `drive` says (plugin or ros_control) in empty.world, its controllers started.
class Racer {
 public:
  explicit Racer(const std::string& drive)
      : parameters_(ParameterTree::fromYaml(
            test::readFile(test::packageFile("tianracer_description", "config/control.yaml")),
            "control.yaml")),
        simulation_(test::shippedWorld("empty.world"), options()) {
    const std::string urdf =
        test::expandXacro("tianracer_description", "urdf/tianracer.urdf.xacro", {"drive:=" + drive});
    model_ = test::parseQuietly(urdf, "tianracer " + drive);
    robot_ = &simulation_.spawn("tianracer", model_, {});
  }
  SimulationOptions options() {
    SimulationOptions options;
    options.parameters = &parameters_;
    return options;
  }
  /// cmd_vel (v, w) to the Ackermann plugin.
  void commandPlugin(double linear, double angular) {
    Twist twist;
    twist.linear.x() = linear;
    twist.angular.z() = angular;
    auto& drive = *test::pluginsOf<AckermannDrive>(*robot_).at(0);
    ASSERT_EQ(std::get<InputHandler<Twist>>(drive.ports().inputs.at(0).sink)(twist, simulation_.time()), "");
  }
  /// cmd_vel (v, w) to the six controllers, as ackermann_joint_commander turns it into their commands.
  void commandControllers(double linear, double angular) {
    AckermannConfig config;
    config.left_steering_joint = "left_steering_hinge_joint";
    config.right_steering_joint = "right_steering_hinge_joint";
    config.front_left_joint = "left_front_wheel_joint";
    config.front_right_joint = "right_front_wheel_joint";
    config.rear_left_joint = "left_rear_wheel_joint";
    config.rear_right_joint = "right_rear_wheel_joint";
    Diagnostics diagnostics("tianracer");
    readAckermannGeometry(model_, "", config, diagnostics);
    ASSERT_THAT(diagnostics.errors(), ::testing::IsEmpty());
    const AckermannJointCommands wanted = ackermannJointCommands(config, linear, angular);
    const std::vector<std::pair<std::string, double>> commands = {
        {"left_steering_hinge_position_controller", wanted.left_steering},
        {"right_steering_hinge_position_controller", wanted.right_steering},
        {"left_front_wheel_velocity_controller", wanted.front_left},
        {"right_front_wheel_velocity_controller", wanted.front_right},
        {"left_rear_wheel_velocity_controller", wanted.rear_left},
        {"right_rear_wheel_velocity_controller", wanted.rear_right}};
    auto& manager = test::pluginsOf<RosControl>(*robot_).at(0)->controllerManager();
    std::vector<std::string> names;
    for (const auto& command : commands) names.push_back(command.first);
    test::startControllers(manager, names, simulation_.time());
    for (const auto& [name, value] : commands) {
      const auto& input =
          std::get<InputHandler<Float64Command>>(manager.find(name)->ports().inputs.at(0).sink);
      ASSERT_EQ(input({value}, simulation_.time()), "") << name;
    }
  }
  void stepFor(double seconds) {
    for (long k = std::lround(seconds / simulation_.stepSize()); k > 0; --k) simulation_.step();
  }
  /// The midpoint of the rear axle on the floor, and the heading [rad].
  Eigen::Vector3d rearAxle() const {
    const Eigen::Vector3d middle = (robot_->body().linkPose("left_rear_wheel").translation() +
                                    robot_->body().linkPose("right_rear_wheel").translation()) /
                                   2;
    const Eigen::Vector3d ahead =
        robot_->body().linkPose("base_footprint").linear() * Eigen::Vector3d::UnitX();
    return {middle.x(), middle.y(), std::atan2(ahead.y(), ahead.x())};
  }

 private:
  TreeParameters parameters_;
  Simulation simulation_;
  ModelSpec model_;
  Robot* robot_ = nullptr;
};

/// Where the bicycle model takes the rear axle's midpoint (x, y, heading) from `from` in `seconds` at (v, w):
/// on a circle of radius v / w, turning at w.
Eigen::Vector3d bicycle(const Eigen::Vector3d& from, double v, double w, double seconds) {
  const double radius = v / w, heading = from.z() + w * seconds;
  return {from.x() + radius * (std::sin(heading) - std::sin(from.z())),
          from.y() + radius * (std::cos(from.z()) - std::cos(heading)), heading};
}

/// Where (x, y, heading) pose `to` is seen from pose `from`.
Eigen::Vector3d travelled(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const Eigen::Vector2d step =
      Eigen::Rotation2Dd(-from.z()) * Eigen::Vector2d(to.x() - from.x(), to.y() - from.y());
  return {step.x(), step.y(), to.z() - from.z()};
}

/// The distance [m] between two (x, y, heading) poses, and their headings' difference [rad].
std::pair<double, double> apart(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return {std::hypot(a.x() - b.x(), a.y() - b.y()), std::abs(std::remainder(a.z() - b.z(), 2 * M_PI))};
}

TEST(TianracerBothWays, ThePluginAndRosControlDriveTheBicycleModelsArc) {
  constexpr double v = 1.0, w = 0.5, spin_up = 1.0, seconds = 5.0;
  Racer plugin("plugin"), controlled("ros_control");
  EXPECT_LT(apart(plugin.rearAxle(), controlled.rearAxle()).first, 1e-6) << "both spawn alike";
  plugin.commandPlugin(v, w);
  controlled.commandControllers(v, w);
  plugin.stepFor(spin_up);  // the car gathers speed: the bicycle model starts from where it is then
  controlled.stepFor(spin_up);
  const Eigen::Vector3d plugin_start = plugin.rearAxle(), controlled_start = controlled.rearAxle();
  plugin.stepFor(seconds);
  controlled.stepFor(seconds);
  const Eigen::Vector3d a = plugin.rearAxle(), b = controlled.rearAxle();
  // The two gather speed through different motors (the plugin's, the controllers' PIDs): the arcs they then
  // drive, each seen from where it started, are the same.
  const auto [distance, turn] = apart(travelled(plugin_start, a), travelled(controlled_start, b));
  EXPECT_LT(distance, 0.1) << "plugin and ros_control";
  EXPECT_LT(turn, 0.1) << "plugin and ros_control";
  for (const auto& [way, from, to] :
       {std::tuple{"plugin", plugin_start, a}, {"ros_control", controlled_start, b}}) {
    const auto [off, off_heading] = apart(to, bicycle(from, v, w, seconds));
    EXPECT_LT(off, 0.1) << way << " and the bicycle model";
    EXPECT_LT(off_heading, 0.1) << way << " and the bicycle model";
  }
}

}  // namespace
}  // namespace bullet_sim
