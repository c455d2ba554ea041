// Self-collision as Gazebo means it. SDF's rule on a chain of boxes (fixtures/self_collision/chain.urdf):
// two links collide when either has <selfCollide>, never when a joint joins them. Moving meshes split into
// convex parts by CoACD, bounded in time and parts, kept in a cache. And a six-axis arm of mesh links that
// all self-collide (six_axis_arm.urdf, written by make_arm.py): held by its position controllers it keeps
// still at its zero pose, then follows a trajectory; colliding by its links' hulls instead throws its wrist.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "bullet_sim/model/convex_decomposition.h"
#include "bullet_sim/assets/mesh.h"
#include "plugins/ros_control/joint_trajectory_controller.h"
#include "plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Action = FollowJointTrajectoryAction;
using Report = GoalReports<Action>::Report;

using test::TemporaryFolder;

// SDF's rule ------------------------------------------------------------------------------------------------

/// chain.urdf with <selfCollide> on `self_colliding`, and each of `boxes` (link, origin xyz, size) replacing
/// that link's collision box.
std::string chain(const std::vector<std::string>& self_colliding,
                  const std::vector<std::array<std::string, 3>>& boxes = {}) {
  const std::string urdf = test::readFile(test::fixture("self_collision/chain.urdf"));
  return test::editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    for (const std::string& link : self_colliding) {
      tinyxml2::XMLElement* gazebo = robot.InsertNewChildElement("gazebo");
      gazebo->SetAttribute("reference", link.c_str());
      gazebo->InsertNewChildElement("selfCollide")->SetText("true");
    }
    for (auto* link = robot.FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
      for (const auto& [name, origin, size] : boxes) {
        if (name != link->Attribute("name")) continue;
        tinyxml2::XMLElement* collision = link->FirstChildElement("collision");
        collision->FirstChildElement("origin")->SetAttribute("xyz", origin.c_str());
        tinyxml2::XMLElement* box = collision->FirstChildElement("geometry")->FirstChildElement("box");
        box->SetAttribute("size", size.c_str());
      }
    }
  });
}

/// The largest angle either joint of `urdf` (a chain) turns to in `seconds` [rad].
double largestTurn(const std::string& urdf, double seconds = 0.5) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("chain", test::parseQuietly(urdf, "chain.urdf"), SpawnPose{});
  double largest = 0;
  for (long k = std::lround(seconds / simulation.stepSize()); k > 0; --k) {
    simulation.step();
    for (const char* joint : {"j1", "j2"})
      largest = std::max(largest, std::abs(robot.body().jointPosition(robot.body().jointIndex(joint))));
  }
  return largest;
}

TEST(SelfCollisionRule, LinksWithoutSelfCollideNeverMeet) { EXPECT_LT(largestTurn(chain({})), 1e-9); }

TEST(SelfCollisionRule, OneOfTwoLinksSelfCollidingMakesThemCollide) {
  // link2 overlaps the post by 2 cm: the push turns the chain by about 0.07 rad.
  EXPECT_GT(largestTurn(chain({"link2"})), 0.02);
  EXPECT_GT(largestTurn(chain({"base_link"})), 0.02);
  EXPECT_GT(largestTurn(chain({"base_link", "link2"})), 0.02);
}

TEST(SelfCollisionRule, AThirdLinksFlagDoesNotMakeTheOthersCollide) {
  EXPECT_LT(largestTurn(chain({"link1"})), 1e-9);
}

TEST(SelfCollisionRule, LinksJoinedByAJointNeverCollide) {
  // Every link self-collides; link1 hangs into the post (joined by j1), link2 into link1 (joined by j2), and
  // link2 clears the post.
  const std::string overlapping = chain({"base_link", "link1", "link2"},
                                        {{"link1", "0.15 0.06 -0.1", "0.3 0.05 0.2"},
                                         {"link2", "-0.15 0.02 0", "0.3 0.05 0.05"}});
  EXPECT_LT(largestTurn(overlapping), 1e-9);
}

// Convex parts ----------------------------------------------------------------------------------------------

TriangleMesh armMesh(const std::string& link) {
  std::string error;
  const std::string path = test::fixture("self_collision/meshes/" + link + ".stl");
  auto mesh = loadMesh(path, Eigen::Vector3d::Ones(), &error);
  if (!mesh) throw std::runtime_error(error);
  return *mesh;
}

Eigen::AlignedBox3d boundsOf(const std::vector<Eigen::Vector3d>& points) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : points) box.extend(point);
  return box;
}

TEST(ConvexDecomposer, SplitsAForkIntoPartsThatLeaveTheGapBetweenItsProngsOpen) {
  const TriangleMesh forearm = armMesh("forearm_link");
  TemporaryFolder cache;
  std::string warning;
  const auto parts = ConvexDecomposer(cache.path()).decompose(forearm, Limits{}, &warning);
  ASSERT_TRUE(parts) << warning;
  EXPECT_EQ(warning, "");
  // A beam, a cross plate and two prongs, each within a millimetre of the mesh's bounds.
  EXPECT_GE(parts->hulls.size(), 3u);
  EXPECT_LE(parts->hulls.size(), 6u);
  const Eigen::AlignedBox3d mesh_bounds = boundsOf(forearm.vertices);
  // Where wrist_1 and wrist_2 sit, between the prongs (x 0.28 to 0.5, |y| < 0.045): no part reaches in.
  const Eigen::AlignedBox3d gap(Eigen::Vector3d(0.29, -0.04, -1), Eigen::Vector3d(0.5, 0.04, 1));
  for (const auto& hull : parts->hulls) {
    const Eigen::AlignedBox3d bounds = boundsOf(hull);
    EXPECT_TRUE(Eigen::AlignedBox3d(mesh_bounds).extend(mesh_bounds.max() + Eigen::Vector3d::Constant(1e-3))
                    .extend(mesh_bounds.min() - Eigen::Vector3d::Constant(1e-3))
                    .contains(bounds));
    EXPECT_TRUE(bounds.intersection(gap).isEmpty())
        << bounds.min().transpose() << " to " << bounds.max().transpose();
  }
  // Split once: another decomposer on the same cache, which has no time to run CoACD, finds the same parts.
  Limits no_time;
  no_time.decomposition_seconds = 1e-6;
  const auto cached = ConvexDecomposer(cache.path()).decompose(forearm, no_time, &warning);
  ASSERT_TRUE(cached) << warning;
  EXPECT_EQ(cached->hulls, parts->hulls);
}

TEST(ConvexDecomposer, SplitsAgainWhereTheCacheHoldsSomethingElse) {
  const TriangleMesh wrist = armMesh("wrist_2_link");  // a box: one part
  TemporaryFolder cache;
  std::string warning;
  const auto parts = ConvexDecomposer(cache.path()).decompose(wrist, Limits{}, &warning);
  ASSERT_TRUE(parts) << warning;
  size_t entries = 0;
  for (const auto& entry : fs::directory_iterator(cache.path())) {
    std::ofstream(entry.path(), std::ios::binary | std::ios::trunc) << "bullet_sim convex parts 1\nnot parts";
    ++entries;
  }
  EXPECT_EQ(entries, 1u);
  const auto again = ConvexDecomposer(cache.path()).decompose(wrist, Limits{}, &warning);
  ASSERT_TRUE(again) << warning;
  EXPECT_EQ(again->hulls, parts->hulls);
}

TEST(ConvexDecomposer, PastItsTimeAMeshKeepsItsHullWithOneWarning) {
  const TriangleMesh forearm = armMesh("forearm_link");
  TemporaryFolder cache;
  ConvexDecomposer decomposer(cache.path());
  Limits limits;
  limits.decomposition_seconds = 0.001;
  std::string warning;
  EXPECT_FALSE(decomposer.decompose(forearm, limits, &warning));
  EXPECT_THAT(warning,
              HasSubstr("took longer than 0.001 s (decomposition_seconds): it collides by its hull"));
  warning.clear();
  EXPECT_FALSE(decomposer.decompose(forearm, limits, &warning));
  EXPECT_EQ(warning, "");
}

TEST(ConvexDecomposer, RemembersASplitThatRanOutOfTimeUntilItHasLonger) {
  const TriangleMesh forearm = armMesh("forearm_link");
  TemporaryFolder cache;
  Limits limits;
  limits.decomposition_seconds = 0.001;
  std::string warning;
  EXPECT_FALSE(ConvexDecomposer(cache.path()).decompose(forearm, limits, &warning));
  // The next spawn (another decomposer, as in another process) takes the hull at once, and says why.
  EXPECT_FALSE(ConvexDecomposer(cache.path()).decompose(forearm, limits, &warning));
  EXPECT_THAT(warning, HasSubstr("took longer than 0.001 s (decomposition_seconds) before"));
  EXPECT_THAT(warning, HasSubstr("a longer decomposition_seconds tries again"));
  // With more time it splits, and remembers the parts instead.
  warning.clear();
  const auto parts = ConvexDecomposer(cache.path()).decompose(forearm, Limits{}, &warning);
  ASSERT_TRUE(parts) << warning;
  const auto cached = ConvexDecomposer(cache.path()).decompose(forearm, limits, &warning);
  ASSERT_TRUE(cached) << warning;
  EXPECT_EQ(cached->hulls, parts->hulls);
}

TEST(ConvexDecomposer, GivesAtMostMaxConvexPartsAndNoneForOne) {
  const TriangleMesh forearm = armMesh("forearm_link");  // a beam, a cross plate and two prongs
  TemporaryFolder cache;
  ConvexDecomposer decomposer(cache.path());
  Limits limits;
  limits.max_convex_parts = 2;
  std::string warning;
  const auto parts = decomposer.decompose(forearm, limits, &warning);
  ASSERT_TRUE(parts) << warning;
  EXPECT_LE(parts->hulls.size(), 2u);
  limits.max_convex_parts = 1;
  EXPECT_FALSE(decomposer.decompose(forearm, limits, &warning));
  EXPECT_EQ(warning, "");
}

// The six-axis arm ------------------------------------------------------------------------------------------

/// One cache for the arm's tests, so that CoACD splits its meshes once per run of this file.
const fs::path& armCache() {
  static const TemporaryFolder folder;
  return folder.path();
}

const std::vector<std::string> kJoints = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                          "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};
const std::vector<std::string> kLinks = {"base_link",    "shoulder_link", "upper_arm_link", "forearm_link",
                                         "wrist_1_link", "wrist_2_link",  "wrist_3_link"};

/// The position trajectory controller of the arm, as its control.yaml would give it, under /arm.
std::string armYaml() {
  std::string yaml =
      "arm:\n  arm_controller:\n    type: position_controllers/JointTrajectoryController\n    joints: [";
  for (const auto& joint : kJoints) yaml += joint + (joint == kJoints.back() ? "]\n" : ", ");
  yaml += "    constraints:\n      goal_time: 0.5\n      stopped_velocity_tolerance: 0.05\n";
  for (const auto& joint : kJoints) yaml += "      " + joint + ": {trajectory: 0.05, goal: 0.01}\n";
  return yaml;
}

/// six_axis_arm.urdf spawned as "arm" in the empty world, its trajectory controller running.
class SixAxisArm {
 public:
  explicit SixAxisArm(const std::string& cache_dir, const Limits& limits = {})
      : parameters_(ParameterTree::fromYaml(armYaml(), "control.yaml")),
        simulation_(world(), options(cache_dir, limits)) {
    const std::string path = test::fixture("self_collision/six_axis_arm.urdf");
    std::vector<std::string> warnings;
    const ModelSpec model = test::parseQuietly(test::readFile(path), path);
    robot_ = &simulation_.spawn("arm", model, SpawnPose{}, &warnings);
    for (const auto& warning : warnings) ADD_FAILURE() << "unexpected spawn warning: " << warning;
    ControllerManager& manager = test::pluginsOf<RosControl>(*robot_).at(0)->controllerManager();
    test::startControllers(manager, {"arm_controller"}, simulation_.time());
    controller_ = &dynamic_cast<JointTrajectoryController&>(*manager.find("arm_controller"));
    for (const auto& link : kLinks) {
      const TriangleMesh& mesh = *robot_->body().spec().link(link)->collisions.at(0).shape.mesh;
      const Eigen::AlignedBox3d box = boundsOf(mesh.vertices);
      for (int corner = 0; corner < 8; ++corner) {
        corners_.emplace_back(link, box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
        start_.push_back(robot_->body().linkPose(link) * corners_.back().second);
      }
    }
  }

  /// Steps for `seconds`; the farthest any corner of a link's mesh bounds got from where it spawned [m].
  double stepAndMeasure(double seconds) {
    for (long k = std::lround(seconds / simulation_.stepSize()); k > 0; --k) {
      step();
      for (size_t c = 0; c < corners_.size(); ++c) {
        const auto& [link, corner] = corners_[c];
        farthest_ = std::max(farthest_, (robot_->body().linkPose(link) * corner - start_[c]).norm());
      }
    }
    return farthest_;
  }

  /// Sends `trajectory` as a goal and steps until it ends; its end report.
  std::optional<Report> follow(const JointTrajectory& trajectory) {
    Action::Goal goal;
    goal.trajectory = trajectory;
    const auto& action = std::get<ActionHandlers<Action>>(controller_->ports().actions.at(0).sink);
    EXPECT_TRUE(action.goal(1, goal, simulation_.time()).accepted);
    std::optional<Report> end;
    test::stepUntil(
        simulation_,
        [&] {
          states_.push_back(controller_->state());
          for (auto& report : action.reports->take())
            if (report.end) end = report;
          return end.has_value();
        },
        trajectory.points.back().time_from_start + 1.0, "the goal's end");
    return end;
  }

  const std::vector<JointTrajectoryControllerState>& states() const { return states_; }
  double time() const { return simulation_.time(); }
  double stepSize() const { return simulation_.stepSize(); }

 private:
  static WorldSpec world() { return test::shippedWorld("empty.world"); }
  SimulationOptions options(const std::string& cache_dir, const Limits& limits) {
    SimulationOptions options;
    options.parameters = &parameters_;
    options.limits = limits;
    options.convex_cache_dir = cache_dir;
    return options;
  }
  void step() { simulation_.step(); }

  TreeParameters parameters_;
  Simulation simulation_;
  Robot* robot_ = nullptr;
  JointTrajectoryController* controller_ = nullptr;
  std::vector<std::pair<std::string, Eigen::Vector3d>> corners_;  ///< link, corner in its frame
  std::vector<Eigen::Vector3d> start_;                            ///< each corner where the arm spawned
  double farthest_ = 0;
  std::vector<JointTrajectoryControllerState> states_;
};

TEST(SixAxisArm, HeldAtItsZeroPoseNoLinkMovesAMillimetre) {
  SixAxisArm arm(armCache());
  EXPECT_LT(arm.stepAndMeasure(2.0), 1e-3);
}

TEST(SixAxisArm, FollowsATrajectoryWithinAHundredthOfARadian) {
  SixAxisArm arm(armCache());
  arm.stepAndMeasure(0.1);
  // Up and out, across, and back, the wrists turning too; nothing touches on the way.
  JointTrajectory trajectory;
  trajectory.joint_names = kJoints;
  trajectory.points = {{{0.4, -0.4, 0.6, 0.3, 0.1, 0.8}, {}, {}, {}, 1.0},
                       {{-0.3, -0.6, 0.9, -0.4, -0.1, -0.5}, {}, {}, {}, 2.0},
                       {{0, 0, 0, 0, 0, 0}, {}, {}, {}, 3.0}};
  const double start = arm.time() + arm.stepSize();
  const auto end = arm.follow(trajectory);
  ASSERT_TRUE(end);
  EXPECT_EQ(*end->end, GoalEnd::kSucceeded) << end->result.error_string;
  double worst = 0;
  size_t waypoints = 0;
  for (const auto& state : arm.states()) {
    for (double error : state.error.positions) worst = std::max(worst, std::abs(error));
    for (const auto& point : trajectory.points) {
      if (std::abs(state.stamp - (start + point.time_from_start)) > arm.stepSize() / 2) continue;
      ++waypoints;
      for (size_t j = 0; j < kJoints.size(); ++j)
        EXPECT_NEAR(state.actual.positions[j], point.positions[j], 0.01)
            << kJoints[j] << " at " << state.stamp;
    }
  }
  EXPECT_EQ(waypoints, 3u);
  EXPECT_LT(worst, 0.01) << "the largest position error on the way [rad]";
}

TEST(SixAxisArm, CollidingByHullsWouldPushItsWristOff) {
  // What the convex parts prevent: the forearm's hull fills the gap between its prongs, where wrist_2 sits,
  // and pushes it off the pose the parts hold within a millimetre (3.6 mm in 1 s; with Bullet's 4 cm margin
  // on the hulls, the wrist was thrown).
  Limits hulls;
  hulls.max_convex_parts = 1;
  SixAxisArm arm(armCache(), hulls);
  EXPECT_GT(arm.stepAndMeasure(1.0), 2e-3);
}

}  // namespace
}  // namespace bullet_sim
