// PID joint control against closed forms: a disc of inertia I on a vertical joint (pid_arm.urdf), pushed by
// effort_controllers' PID loops or by Gazebo's pid_gains, settles as the textbook first- and second-order
// systems do.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "plugins/ros_control/pid.h"
#include "plugins/ros_control/pid_joint_controllers.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

constexpr double kInertia = 0.1;  // [kg m^2] of each disc about its joint

/// `yaml` under the namespace `ns`, as `rosparam load` puts it in a <group ns>.
std::string inNamespace(const std::string& ns, const std::string& yaml) {
  std::string nested = ns + ":\n";
  std::istringstream lines(yaml);
  for (std::string line; std::getline(lines, line);) nested += "  " + line + "\n";
  return nested;
}

/// pid_arm.urdf (its transmissions edited by `edit`), spawned as "arm" in empty.world with `yaml` in its
/// namespace, /arm, where ros_control lives for a robot without <robotNamespace>.
class PidArm {
 public:
  template <class Edit>
  PidArm(const std::string& yaml, Edit edit)
      : parameters_(ParameterTree::fromYaml(inNamespace("arm", yaml), "parameters")),
        simulation_(test::shippedWorld("empty.world"), options()) {
    const std::string urdf = test::editUrdf(test::readFile(test::fixture("robots/pid_arm.urdf")), edit);
    robot_ = &simulation_.spawn("arm", test::parseQuietly(urdf, "pid_arm.urdf"), SpawnPose{});
    manager_ = &test::pluginsOf<RosControl>(*robot_).at(0)->controllerManager();
  }
  explicit PidArm(const std::string& yaml) : PidArm(yaml, [](tinyxml2::XMLElement&) {}) {}

  SimulationOptions options() {
    SimulationOptions options;
    options.parameters = &parameters_;
    return options;
  }
  void start(const std::string& controller) {
    test::startControllers(*manager_, {controller}, simulation_.time());
  }
  void command(const std::string& controller, double value) {
    const auto& handler =
        std::get<InputHandler<Float64Command>>(manager_->find(controller)->ports().inputs.at(0).sink);
    ASSERT_EQ(handler({value}, simulation_.time()), "");
  }
  double position(const std::string& joint) {
    return robot_->body().jointPosition(robot_->body().jointIndex(joint));
  }
  double velocity(const std::string& joint) {
    return robot_->body().jointVelocity(robot_->body().jointIndex(joint));
  }
  void stepFor(double seconds) {
    for (long k = std::lround(seconds / simulation_.stepSize()); k > 0; --k) simulation_.step();
  }
  ControllerManager& manager() { return *manager_; }

 private:
  TreeParameters parameters_;
  Simulation simulation_;
  Robot* robot_ = nullptr;
  ControllerManager* manager_ = nullptr;
};

TEST(PidControllers, PositionLoopRingsDownAsADampedOscillator) {
  // I x'' = p (1 - x) - d x' with p = I w^2, d = 2 z w I: w = 10 rad/s, z = 0.5. control_toolbox takes the
  // error's derivative from the last error, so the step in the set point kicks the disc to x'(0) = d / I.
  const double w = 10, z = 0.5, p = kInertia * w * w, d = 2 * z * w * kInertia;
  PidArm arm("arm_controller:\n  type: effort_controllers/JointPositionController\n  joint: arm_joint\n"
             "  pid: {p: " + std::to_string(p) + ", d: " + std::to_string(d) + "}\n");
  arm.start("arm_controller");
  arm.stepFor(0.1);
  ASSERT_NEAR(arm.position("arm_joint"), 0, 1e-6);  // started where it stood
  arm.command("arm_controller", 1.0);
  const double wd = w * std::sqrt(1 - z * z), v0 = d / kInertia;
  double elapsed = 0;
  for (double t : {0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0}) {
    arm.stepFor(t - elapsed);
    elapsed = t;
    const double expected =
        1 - std::exp(-z * w * t) * (std::cos(wd * t) - (v0 - z * w) / wd * std::sin(wd * t));
    EXPECT_NEAR(arm.position("arm_joint"), expected, 0.005) << "at t = " << t << " s";
  }
  arm.stepFor(1.0);
  EXPECT_NEAR(arm.position("arm_joint"), 1.0, 1e-3);  // settled: e^(-z w t) < 1e-4 by t = 2 s
  EXPECT_NEAR(arm.velocity("arm_joint"), 0.0, 1e-2);

  // Its state: every 10th update, the set point, where the joint is, the effort and the gains.
  const auto& state = *std::get<const Stream<JointControllerState>*>(
      arm.manager().find("arm_controller")->ports().outputs.at(0).stream);
  EXPECT_DOUBLE_EQ(state.latest().set_point, 1.0);
  EXPECT_NEAR(state.latest().process_value, 1.0, 1e-3);
  EXPECT_NEAR(state.latest().time_step, 0.001, 1e-9);
  EXPECT_DOUBLE_EQ(state.latest().p, p);
  EXPECT_DOUBLE_EQ(state.latest().d, d);
}

TEST(PidControllers, VelocityLoopRisesAsAFirstOrderLag) {
  // I w' = p (w* - w): w(t) = w* (1 - e^(-t / tau)) with tau = I / p = 0.1 s.
  PidArm arm("spin_controller:\n  type: effort_controllers/JointVelocityController\n  joint: spin_joint\n"
             "  pid: {p: 1.0}\n");
  arm.start("spin_controller");
  arm.command("spin_controller", 2.0);
  const double tau = kInertia / 1.0;
  double elapsed = 0;
  for (double t : {tau, 2 * tau, 5 * tau}) {
    arm.stepFor(t - elapsed);
    elapsed = t;
    EXPECT_NEAR(arm.velocity("spin_joint"), 2.0 * (1 - std::exp(-t / tau)), 0.005) << "at t = " << t << " s";
  }
}

TEST(PidControllers, GazeboPidGainsTurnAVelocityJointIntoAPidLoop) {
  // DefaultRobotHWSim with gazebo_ros_control/pid_gains/spin_joint pushes the joint by effort towards a
  // velocity_controllers/JointVelocityController's command: the same first-order lag.
  PidArm arm(
      "gazebo_ros_control: {pid_gains: {spin_joint: {p: 1.0}}}\n"
      "spin_controller: {type: velocity_controllers/JointVelocityController, joint: spin_joint}\n",
      [](tinyxml2::XMLElement& robot) {
        auto* spin = robot.FirstChildElement("transmission")->NextSiblingElement("transmission");
        spin->FirstChildElement("joint")->FirstChildElement("hardwareInterface")->SetText(
            "hardware_interface/VelocityJointInterface");
      });
  arm.start("spin_controller");
  arm.command("spin_controller", 2.0);
  arm.stepFor(0.1);
  EXPECT_NEAR(arm.velocity("spin_joint"), 2.0 * (1 - std::exp(-1.0)), 0.005);
  arm.stepFor(0.9);
  EXPECT_NEAR(arm.velocity("spin_joint"), 2.0, 1e-3);
}

TEST(Pid, ClampsTheIntegralTermAsControlToolboxDoes) {
  // Without antiwindup the integral grows unbounded but its term is clipped to [i_clamp_min, i_clamp]; with
  // it, the integral itself stops at i_clamp / i. The derivative of a constant error is 0 after the first.
  Pid plain({0, 2, 0, 1.0, -1.0, false});
  Pid antiwindup({0, 2, 0, 1.0, -1.0, true});
  for (int k = 0; k < 100; ++k) {
    plain.compute(1.0, 0.1);
    antiwindup.compute(1.0, 0.1);
  }
  EXPECT_DOUBLE_EQ(plain.compute(1.0, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(plain.compute(-1.0, 0.1), 1.0);  // the integral, 10 s of error 1, still saturates
  EXPECT_DOUBLE_EQ(antiwindup.compute(-1.0, 0.1), 2 * (0.5 - 0.1));
  EXPECT_EQ(plain.compute(1.0, 0.0), 0.0);  // no time: no command
  const auto gains = Pid::gainsFrom(ParameterTree::fromYaml("{p: 3, i_clamp: -2, i_clamp_max: 5}", "gains"));
  ASSERT_TRUE(gains);
  EXPECT_DOUBLE_EQ(gains->i_max, 5);
  EXPECT_DOUBLE_EQ(gains->i_min, -2);
  EXPECT_FALSE(Pid::gainsFrom(ParameterTree::fromYaml("{i: 3}", "gains")));
}

}  // namespace
}  // namespace bullet_sim
