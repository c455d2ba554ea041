// An effort-driven look-alike of ur_gazebo's UR5 (B11 in the robot survey): the six-axis arm of mesh links
// that all self-collide (test/fixtures/self_collision/six_axis_arm.urdf), fixed to the world, with the UR5's
// link masses (its inertias scaled with them), no joint damping, effort transmissions and the effort
// JointTrajectoryController gains of ur5_controllers.yaml. Each joint carries the weight beyond it with a PD
// loop, so it sags by that torque over its p gain: held, the arm settles there and stays; following a 2 s
// trajectory, no joint lags by more than the torque its links' weight and inertia can ask of it, over p.
// Colliding by its links' hulls (as every moving mesh did before they had convex parts), the hulls' fight
// pins efforts at their limits and the arm never arrives: what the survey saw of the UR5.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <unistd.h>

#include "plugins/ros_control/joint_trajectory_controller.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

constexpr double kGravity = 9.81;  // [m/s^2]

const std::vector<std::string> kJoints = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                          "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};
/// The link each joint turns, and every link after it in the chain.
const std::vector<std::string> kLinks = {"shoulder_link", "upper_arm_link", "forearm_link",
                                         "wrist_1_link",  "wrist_2_link",   "wrist_3_link"};
/// ur_description's UR5 masses [kg] for the links of kLinks.
const std::vector<double> kMasses = {3.7, 8.393, 2.275, 1.219, 1.219, 0.1879};
/// ur5_controllers.yaml's gains (p, d, i, i_clamp), in kJoints' order.
const std::vector<std::string> kGains = {
    "{p: 4000, d: 200, i: 1, i_clamp: 1}", "{p: 10000, d: 200, i: 1, i_clamp: 1}",
    "{p: 2000, d: 20, i: 1, i_clamp: 1}",  "{p: 500, d: 1, i: 1, i_clamp: 1}",
    "{p: 500, d: 1, i: 1, i_clamp: 1}",    "{p: 10, d: 0.1, i: 0, i_clamp: 1}"};
const std::vector<double> kP = {4000, 10000, 2000, 500, 500, 10};  // [N m/rad], from kGains
const std::vector<double> kI = {1, 1, 1, 1, 1, 0};                  // [N m/(rad s)]
constexpr double kIClamp = 1;                                        // [N m]
const std::vector<double> kEffortLimits = {150, 150, 150, 28, 28, 28};  // [N m], the UR5's and the arm's

/// ur5_controllers.yaml's effort trajectory controller, for the arm's joints, under /arm.
std::string controllerYaml() {
  std::string yaml =
      "arm:\n  arm_controller:\n    type: effort_controllers/JointTrajectoryController\n    joints: [";
  for (const auto& joint : kJoints) yaml += joint + (joint == kJoints.back() ? "]\n" : ", ");
  yaml += "    gains:\n";
  for (size_t j = 0; j < kJoints.size(); ++j) yaml += "      " + kJoints[j] + ": " + kGains[j] + "\n";
  yaml += "    constraints:\n      goal_time: 0.6\n      stopped_velocity_tolerance: 0.05\n";
  for (const auto& joint : kJoints) yaml += "      " + joint + ": {trajectory: 0.1, goal: 0.1}\n";
  return yaml + "    stop_trajectory_duration: 0.5\n";
}

/// six_axis_arm.urdf as a UR5 look-alike: UR5 masses, inertias scaled with them, no damping, effort joints.
std::string lookAlikeUrdf() {
  const std::string path = test::fixture("self_collision/six_axis_arm.urdf");
  return test::editUrdf(test::readFile(path), [](tinyxml2::XMLElement& robot) {
    for (auto* link = robot.FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
      const auto at = std::find(kLinks.begin(), kLinks.end(), link->Attribute("name"));
      if (at == kLinks.end()) continue;
      auto* mass = link->FirstChildElement("inertial")->FirstChildElement("mass");
      const double scale = kMasses[at - kLinks.begin()] / mass->DoubleAttribute("value");
      mass->SetAttribute("value", kMasses[at - kLinks.begin()]);
      auto* inertia = link->FirstChildElement("inertial")->FirstChildElement("inertia");
      for (const char* entry : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"})
        inertia->SetAttribute(entry, inertia->DoubleAttribute(entry) * scale);
    }
    for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint"))
      if (auto* dynamics = joint->FirstChildElement("dynamics")) joint->DeleteChild(dynamics);
    for (auto* t = robot.FirstChildElement("transmission"); t; t = t->NextSiblingElement("transmission"))
      t->FirstChildElement("joint")->FirstChildElement("hardwareInterface")->SetText(
          "hardware_interface/EffortJointInterface");
  });
}

/// A folder for the arm's convex parts, so that CoACD splits its meshes once per run of this file.
struct ConvexCache {
  const std::string name = "bullet_sim_effort_arm_" + std::to_string(getpid());
  const std::string path = std::filesystem::temp_directory_path() / name;
  ~ConvexCache() { std::filesystem::remove_all(path); }
};
const ConvexCache& convexCache() {
  static const ConvexCache cache;
  return cache;
}

/// The look-alike spawned as "arm" in the empty world, its trajectory controller started at once.
class EffortArm {
 public:
  explicit EffortArm(const Limits& limits)
      : parameters_(ParameterTree::fromYaml(controllerYaml(), "ur5_controllers.yaml")),
        simulation_(test::shippedWorld("empty.world"), options(limits)) {
    robot_ = &simulation_.spawn("arm", test::parseQuietly(lookAlikeUrdf(), "effort arm"), SpawnPose{});
    ControllerManager& manager = test::pluginsOf<RosControl>(*robot_).at(0)->controllerManager();
    test::startControllers(manager, {"arm_controller"}, simulation_.time());
    controller_ = &dynamic_cast<JointTrajectoryController&>(*manager.find("arm_controller"));
  }

  void stepFor(double seconds) {
    for (long k = std::lround(seconds / simulation_.stepSize()); k > 0; --k) {
      simulation_.step();
      states_.push_back(controller_->state());
    }
  }
  /// Sends `trajectory` on the controller's command topic.
  void command(const JointTrajectory& trajectory) {
    const auto& input = std::get<InputHandler<JointTrajectory>>(controller_->ports().inputs.at(0).sink);
    ASSERT_EQ(input(trajectory, simulation_.time()), "");
  }
  double position(size_t joint) const { return body().jointPosition(body().jointIndex(kJoints[joint])); }
  double effort(size_t joint) const { return body().jointEffort(body().jointIndex(kJoints[joint])); }

  /// The torque [N m] gravity exerts about joint `joint` on the links beyond it, where they are now.
  double gravityTorque(size_t joint) const {
    const Eigen::Isometry3d frame = body().linkPose(kLinks[joint]);  // a joint's child frame is at the joint
    const Eigen::Vector3d axis = frame.linear() * body().spec().joint(kJoints[joint])->axis.normalized();
    double torque = 0;
    for (size_t k = joint; k < kLinks.size(); ++k) {
      const InertialSpec& inertial = *body().spec().link(kLinks[k])->inertial;
      const Eigen::Vector3d lever = body().linkPose(kLinks[k]) * inertial.com - frame.translation();
      torque += axis.dot(lever.cross(Eigen::Vector3d(0, 0, -kGravity * inertial.mass)));
    }
    return torque;
  }
  /// Bounds on what the links beyond joint `joint` can ask of it in any pose: their weight's torque [N m] and
  /// their moment of inertia about it [kg m^2], with each link's centre of mass at its farthest, the chain
  /// stretched out (the distances between joints and to the centre of mass add up).
  std::pair<double, double> loadBounds(size_t joint) const {
    double weight = 0, moment = 0, reach = 0;
    for (size_t k = joint; k < kLinks.size(); ++k) {
      const InertialSpec& inertial = *body().spec().link(kLinks[k])->inertial;
      const double farthest = reach + inertial.com.norm();
      weight += kGravity * inertial.mass * farthest;
      moment += inertial.mass * farthest * farthest + inertial.inertia.trace();
      if (k + 1 < kLinks.size()) reach += body().spec().joint(kJoints[k + 1])->origin.translation().norm();
    }
    return {weight, moment};
  }
  const std::vector<JointTrajectoryControllerState>& states() const { return states_; }

 private:
  const RobotBody& body() const { return robot_->body(); }
  SimulationOptions options(const Limits& limits) {
    SimulationOptions options;
    options.parameters = &parameters_;
    options.limits = limits;
    options.convex_cache_dir = convexCache().path;
    return options;
  }

  TreeParameters parameters_;
  Simulation simulation_;
  Robot* robot_ = nullptr;
  JointTrajectoryController* controller_ = nullptr;
  std::vector<JointTrajectoryControllerState> states_;
};

/// Convex parts, as moving meshes have them, or hulls (one part), as they had before.
Limits collidingBy(bool hulls) {
  Limits limits;
  if (hulls) limits.max_convex_parts = 1;
  return limits;
}

/// Out and up (the survey's command to the UR5), the wrists turning too, in 2 s.
JointTrajectory outAndUp() {
  JointTrajectory trajectory;
  trajectory.joint_names = kJoints;
  const std::vector<double> at_rest(kJoints.size(), 0.0);
  trajectory.points.push_back({{0.5, -1.0, 1.0, 0.2, 0.1, 0.8}, at_rest, {}, {}, 2.0});
  return trajectory;
}

TEST(EffortArm, HeldItSagsByItsWeightOverTheGainAndStaysThere) {
  EffortArm arm(collidingBy(/*hulls=*/false));
  arm.stepFor(2.0);
  std::vector<double> settled;
  for (size_t j = 0; j < kJoints.size(); ++j) settled.push_back(arm.position(j));
  arm.stepFor(1.0);
  for (size_t j = 0; j < kJoints.size(); ++j) {
    // p (0 - q) + i_term balances the weight: q = gravity / p, but for the integral term, which has gathered
    // at most i |q| t in the t = 3 s the error has been at most |q|.
    const double sag = arm.gravityTorque(j) / kP[j];
    const auto integral = [&](double seconds) { return kI[j] * std::abs(sag) * seconds / kP[j] + 1e-9; };
    EXPECT_NEAR(arm.position(j), sag, integral(3.0)) << kJoints[j];
    EXPECT_NEAR(arm.position(j), settled[j], integral(1.0)) << kJoints[j] << " wanders";
    EXPECT_LT(std::abs(arm.effort(j)), 0.5 * kEffortLimits[j]) << kJoints[j] << " strains";
  }
  EXPECT_GT(std::abs(arm.gravityTorque(1)), 40) << "[N m] the shoulder carries a UR5's weight";
}

TEST(EffortArm, FollowsATrajectoryWithinWhatItsLoadAsksOverTheGain) {
  EffortArm arm(collidingBy(/*hulls=*/false));
  arm.stepFor(0.5);
  const JointTrajectory trajectory = outAndUp();
  arm.command(trajectory);
  const size_t start = arm.states().size();
  arm.stepFor(3.0);
  // A cubic from rest to rest over T: accelerations up to 6 dq / T^2, speeds up to 1.5 dq / T. Any link turns
  // at most as fast as all joints together.
  double acceleration = 0, speed = 0;
  for (double target : trajectory.points[0].positions) {
    acceleration += 6 * std::abs(target) / 4.0;
    speed += 1.5 * std::abs(target) / 2.0;
  }
  for (size_t j = 0; j < kJoints.size(); ++j) {
    const auto [weight, moment] = arm.loadBounds(j);
    const double bound = (weight + moment * (acceleration + 2 * speed * speed) + kIClamp) / kP[j];
    double worst = 0;
    for (size_t s = start; s < arm.states().size(); ++s)
      worst = std::max(worst, std::abs(arm.states()[s].error.positions[j]));
    EXPECT_LT(worst, bound) << kJoints[j] << " lags";
    // At rest at the goal it sags as held, but for what the integral term gathered in 3.5 s of such lags.
    EXPECT_NEAR(arm.position(j), trajectory.points[0].positions[j] + arm.gravityTorque(j) / kP[j],
                kI[j] * bound * 3.5 / kP[j] + 1e-9)
        << kJoints[j] << " where it arrives";
  }
}

TEST(EffortArm, CollidingByHullsItStrainsAndNeverArrives) {
  EffortArm arm(collidingBy(/*hulls=*/true));
  arm.stepFor(0.5);
  arm.command(outAndUp());
  arm.stepFor(3.0);
  double farthest = 0, strain = 0;
  for (size_t j = 0; j < kJoints.size(); ++j) {
    farthest = std::max(farthest, std::abs(arm.position(j) - outAndUp().points[0].positions[j]));
    strain = std::max(strain, std::abs(arm.effort(j)) / kEffortLimits[j]);
  }
  EXPECT_GT(farthest, 0.1) << "[rad] from the goal";
  EXPECT_GT(strain, 0.99) << "of its effort limit";
}

}  // namespace
}  // namespace bullet_sim
