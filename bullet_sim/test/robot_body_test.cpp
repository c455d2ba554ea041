// Actuating a robot body from outside its joints, on both wheel models and as one rigid body: a wrench on a
// link and the root's velocity, against Newton's laws on a free-floating robot (no gravity, nothing touching
// it).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

/// two_wheeler.urdf with a diff drive on `wheel_model` wheels (that drive holds the wheels still); or, for
/// kRigid, with every joint fixed and no plugin: one rigid body, whose root is off its centre of mass.
const std::string kRigid = "rigid";
ModelSpec twoWheeler(const std::string& wheel_model) {
  const bool rigid = wheel_model == kRigid;
  const std::string urdf = test::twoWheelerWithDiffDrive({{"wheelModel", rigid ? "contact" : wheel_model}});
  ModelSpec model = test::parseQuietly(urdf, "two_wheeler.urdf");
  if (rigid) {
    for (auto& joint : model.joints) joint.type = JointSpec::Type::kFixed;
    model.plugins.clear();
  }
  return model;
}

WorldSpec weightless() {
  WorldSpec world = test::shippedWorld("empty.world");
  world.gravity = Eigen::Vector3d::Zero();
  return world;
}

/// Mass [kg], centre of mass in the root frame [m] and inertia about it in root axes [kg m^2], from the
/// model's inertials at its zero pose.
struct Inertia {
  double mass = 0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
};

Inertia inertiaOf(const ModelSpec& model) {
  Inertia total;
  const auto frames = linkPosesAtZero(model);
  for (const auto& link : model.links) {
    if (!link.inertial) continue;
    total.mass += link.inertial->mass;
    total.com += link.inertial->mass * (frames.at(link.name) * link.inertial->com);
  }
  total.com /= total.mass;
  for (const auto& link : model.links) {
    if (!link.inertial) continue;
    const Eigen::Isometry3d& frame = frames.at(link.name);
    const Eigen::Vector3d offset = frame * link.inertial->com - total.com;
    const Eigen::Matrix3d inertia = frame.linear() * link.inertial->inertia * frame.linear().transpose();
    total.tensor += inertia + link.inertial->mass * (offset.squaredNorm() * Eigen::Matrix3d::Identity() -
                                                     offset * offset.transpose());
  }
  return total;
}

class RobotBodyActuation : public ::testing::TestWithParam<std::string> {};

TEST_P(RobotBodyActuation, AForceThroughTheCentreOfMassChangesTheVelocityByForceTimesTimeOverMass) {
  Simulation simulation(weightless());
  ModelSpec model = twoWheeler(GetParam());
  const Inertia inertia = inertiaOf(model);
  Robot& robot = simulation.spawn("robot", std::move(model), {.x = 1, .y = 2, .yaw = 0.5, .z = 1.0});
  RobotBody& body = robot.body();
  const Eigen::Vector3d force(3.0, -1.5, 0.6);  // [N]
  const int steps = 500;
  for (int i = 0; i < steps; ++i) {
    // At the root's origin, with the moment that cancels the force's about the centre of mass.
    const Eigen::Isometry3d root = body.linkPose("base_footprint");
    const Eigen::Vector3d lever = root * inertia.com - root.translation();
    body.applyLinkWrench("base_footprint", force, lever.cross(force));
    simulation.step();
  }
  const Eigen::Vector3d expected = force * steps * simulation.stepSize() / inertia.mass;
  EXPECT_LT((body.linkLinearVelocity("base_footprint") - expected).norm(), 1e-6 * expected.norm());
  EXPECT_LT(body.linkAngularVelocity("base_footprint").norm(), 1e-6);
  for (int i = 0; i < 200; ++i) simulation.step();
  EXPECT_LT((body.linkLinearVelocity("base_footprint") - expected).norm(), 1e-6 * expected.norm())
      << "the wrench lasts one step each time it is applied";
}

TEST_P(RobotBodyActuation, ATorqueChangesTheAngularMomentumByTorqueTimesTime) {
  Simulation simulation(weightless());
  ModelSpec model = twoWheeler(GetParam());
  const Inertia inertia = inertiaOf(model);
  Robot& robot = simulation.spawn("robot", std::move(model), {.z = 1.0});
  const double torque = 0.02;  // [N m]
  const int steps = 300;
  for (int i = 0; i < steps; ++i) {
    robot.body().applyLinkWrench("left_wheel", Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, torque));
    simulation.step();
  }
  // The vertical is not a principal axis: the spin follows the inverse inertia (the tilt it brings is tiny).
  const double expected = torque * steps * simulation.stepSize() * inertia.tensor.inverse()(2, 2);
  EXPECT_NEAR(robot.body().linkAngularVelocity("base_link").z(), expected, 1e-4 * expected);
}

TEST_P(RobotBodyActuation, ATiltedRobotTurnsByItsInertiaInWorldAxesFromItsFirstStep) {
  Simulation simulation(weightless());
  ModelSpec model = twoWheeler(GetParam());
  const Inertia inertia = inertiaOf(model);
  const SpawnPose pose{.yaw = 0.4, .z = 1.0, .roll = 0.9, .pitch = -0.5};
  Robot& robot = simulation.spawn("robot", std::move(model), pose);
  const Eigen::Matrix3d rotation = robot.body().linkPose("base_footprint").linear();
  const Eigen::Vector3d torque(0.01, -0.02, 0.03);  // [N m], world axes, for one step
  robot.body().applyLinkWrench("base_link", Eigen::Vector3d::Zero(), torque);
  simulation.step();
  const Eigen::Matrix3d world_inertia = rotation * inertia.tensor * rotation.transpose();
  const Eigen::Vector3d expected = world_inertia.inverse() * torque * simulation.stepSize();
  // Within 1 %: the contact model's wheels turn on their joints, held by motors the solver converges on
  // (0.4 % here). The inertia of the unrotated body, Bullet's until its first step, was 53 % off.
  EXPECT_LT((robot.body().linkAngularVelocity("base_link") - expected).norm(), 1e-2 * expected.norm());
}

TEST_P(RobotBodyActuation, TheRootVelocityIsSetAndTheRobotMovesRigidlyAtIt) {
  Simulation simulation(weightless());
  Robot& robot = simulation.spawn("robot", twoWheeler(GetParam()), {.x = -1, .yaw = 1.0, .z = 1.0});
  RobotBody& body = robot.body();
  const Eigen::Vector3d linear(0.4, -0.3, 0.2), angular(0.1, -0.2, 0.7);
  body.setRootVelocity(linear, angular);
  EXPECT_LT((body.linkLinearVelocity("base_footprint") - linear).norm(), 1e-9);
  EXPECT_LT((body.linkAngularVelocity("base_footprint") - angular).norm(), 1e-9);
  for (const std::string link : {"base_link", "left_wheel", "right_wheel"}) {
    EXPECT_LT((body.linkAngularVelocity(link) - angular).norm(), 1e-9) << link << " turns with the root";
  }
  if (GetParam() != kRigid) {
    EXPECT_EQ(body.jointVelocity(body.jointIndex("left_wheel_joint")), 0);
  }

  const Eigen::Isometry3d start = body.linkPose("base_footprint");
  body.setRootVelocity(linear, Eigen::Vector3d::Zero());
  const int steps = 400;
  for (int i = 0; i < steps; ++i) simulation.step();
  const Eigen::Isometry3d end = body.linkPose("base_footprint");
  EXPECT_LT((end.translation() - start.translation() - linear * steps * simulation.stepSize()).norm(), 1e-9);
  EXPECT_TRUE(end.linear().isApprox(start.linear(), 1e-9));
}

TEST_P(RobotBodyActuation, AWrenchOnALinkThatDoesNotExistIsRefused) {
  Simulation simulation(weightless());
  Robot& robot = simulation.spawn("robot", twoWheeler(GetParam()), {.z = 1.0});
  EXPECT_THROW(
      robot.body().applyLinkWrench("no_such_link", Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero()),
      std::out_of_range);
}

INSTANTIATE_TEST_SUITE_P(WheelModels, RobotBodyActuation, ::testing::ValuesIn(test::kWheelModels));
INSTANTIATE_TEST_SUITE_P(OneRigidBody, RobotBodyActuation, ::testing::Values(kRigid));

}  // namespace
}  // namespace bullet_sim
