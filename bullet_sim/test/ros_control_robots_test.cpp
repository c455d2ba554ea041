// Our own robots driven both ways, in-process: the Yahboom pan/tilt through its joint pose plugin and through
// ros_control (yahboomcar.urdf.xacro pan_tilt:=ros_control, config/pan_tilt_control.yaml) reaches the same
// angles, and its camera sees the same image.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bullet_sim/plugins/joint_position.h"
#include "bullet_sim/plugins/pinhole_camera.h"
#include "bullet_sim/plugins/ros_control/joint_trajectory_controller.h"
#include "bullet_sim/plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/simulation_images.h"
#include "test_support.h"

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
    std::string urdf = test::expandXacro("yahboomcar_description", "urdf/yahboomcar.urdf.xacro",
                                         {"pan_tilt:=" + pan_tilt});
    urdf = test::replaceAfter(urdf, "<sensor name=\"camera\"", "<update_rate>30", "<update_rate>4");
    robot_ = &simulation_->spawn("car", test::parseQuietly(urdf, "yahboomcar " + pan_tilt), {});
    camera_ = robot_->pluginsOf<PinholeCamera>().at(0);
  }

  double angle(const std::string& joint) const {
    return robot_->body().jointPosition(robot_->body().jointIndex(joint));
  }
  /// Steps until the camera has rendered one more frame; that frame.
  const CameraImage& nextFrame() {
    const uint64_t target = camera_->frameCount() + 1;
    test::stepUntil(*simulation_, [&] { return camera_->frameCount() >= target; }, 1.0, "a camera frame");
    return camera_->image();
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
  PinholeCamera* camera_ = nullptr;
};

/// The mean absolute difference of two images' bytes.
double meanDifference(const CameraImage& a, const CameraImage& b) {
  EXPECT_EQ(a.data.size(), b.data.size());
  double sum = 0;
  for (size_t i = 0; i < a.data.size() && i < b.data.size(); ++i) sum += std::abs(int(a.data[i]) - int(b.data[i]));
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
  auto& pan_tilt = *plugin.robot().pluginsOf<JointPosition>().at(0);
  const auto& command = std::get<InputHandler<JointTrajectory>>(pan_tilt.ports().inputs.at(0).sink);
  ASSERT_EQ(command(panTiltTo(kPan, kTilt, 0), plugin.simulation().time()), "");
  plugin.stepFor(1.5);

  PanTiltCar controlled("ros_control");
  auto& manager = controlled.robot().pluginsOf<RosControl>().at(0)->controllerManager();
  test::startControllers(manager, {"pan_tilt_controller"}, controlled.simulation().time());
  auto& controller = dynamic_cast<JointTrajectoryController&>(*manager.find("pan_tilt_controller"));
  const auto& action = std::get<ActionHandlers<FollowJointTrajectoryAction>>(controller.ports().actions.at(0).sink);
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

}  // namespace
}  // namespace bullet_sim
