// Actuating a robot body from outside its joints, on both wheel models and as one rigid body: a wrench on a
// link, the root's velocity, and a free wheel's joint damping and friction, against Newton's laws on a
// free-floating robot (no gravity, nothing touching it).
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

/// two_wheeler with its caster on a free axle (a wheel no drive turns, of kWheelInertia), damped by
/// `damping` [N m s/rad] with dry `friction` [N m], and its chassis a hundred times heavier: the wheel's
/// reaction on it, which the contact model has and the raycast one leaves out, is then below 1e-4.
/// The caster's spin [rad/s] after `effort` [N m] spun it in the air for `seconds`, then at every step of
/// `coast` seconds.
constexpr double kWheelInertia = 2.5e-4;  // [kg m^2] about the axle
std::vector<double> coastingSpin(const std::string& wheel_model, double damping, double friction,
                                 double effort, double seconds, double coast) {
  ModelSpec model = twoWheeler(wheel_model);
  for (auto& joint : model.joints) {
    if (joint.name != "caster_joint") continue;
    joint.type = JointSpec::Type::kContinuous;
    joint.axis = Eigen::Vector3d::UnitY();
    joint.damping = damping;
    joint.friction = friction;
  }
  for (auto& link : model.links) {
    const Eigen::Matrix3d wheel = Eigen::Vector3d(1.4e-4, kWheelInertia, 1.4e-4).asDiagonal();
    if (link.name == "caster") link.inertial = InertialSpec{0.2, Eigen::Vector3d::Zero(), wheel};
    if (link.name == "base_link") link.inertial->mass *= 100, link.inertial->inertia *= 100;
  }
  Simulation simulation(weightless());
  RobotBody& body = simulation.spawn("robot", std::move(model), {.z = 1.0}).body();
  const int caster = body.jointIndex("caster_joint");
  while (simulation.time() < seconds - 1e-9) {
    body.applyJointEffort(caster, effort);
    simulation.step();
  }
  std::vector<double> spins{body.jointVelocity(caster)};
  while (simulation.time() < seconds + coast - 1e-9) {
    simulation.step();
    spins.push_back(body.jointVelocity(caster));
  }
  return spins;
}

// Gazebo damps a joint by -damping * rate, on every wheel model: a free wheel's spin decays as
// exp(-damping t / inertia) (the explicit steps take 0.5 % more over these 400). The raycast model ignored a
// joint's <dynamics> altogether.
class FreeWheel : public ::testing::TestWithParam<std::string> {};

TEST_P(FreeWheel, AJointsDampingSlowsItExponentially) {
  const double damping = 1.25e-3;  // [N m s/rad]: 0.2 s on the wheel's inertia
  const std::vector<double> spins = coastingSpin(GetParam(), damping, 0, 0.01, 0.2, 0.4);
  ASSERT_GT(spins.front(), 5.0) << "the effort spun the wheel";
  const double expected = spins.front() * std::exp(-damping * 0.4 / kWheelInertia);
  EXPECT_NEAR(spins.back(), expected, 0.01 * expected);
  const std::vector<double> undamped = coastingSpin(GetParam(), 0, 0, 0.01, 0.2, 0.4);
  EXPECT_NEAR(undamped.front(), 0.01 * 0.2 / kWheelInertia, 1e-3 * undamped.front());
  EXPECT_NEAR(undamped.back(), undamped.front(), 1e-3 * undamped.front()) << "nothing else slows it";
}

// Dry joint friction (ODE's joint motor at rest, its force limit the friction) takes friction / inertia of
// spin each second, and stops the wheel without turning it back: 0.01 N m against 0.002 for 0.2 s spins it
// to 6.4 rad/s, which 8 rad/s^2 takes away in 0.8 s.
TEST_P(FreeWheel, AJointsDryFrictionStopsItAtAConstantRate) {
  const double friction = 0.002, effort = 0.01;  // [N m]
  const std::vector<double> spins = coastingSpin(GetParam(), 0, friction, effort, 0.2, 1.2);
  EXPECT_NEAR(spins.front(), (effort - friction) * 0.2 / kWheelInertia, 0.01 * 6.4);
  EXPECT_NEAR(spins.at(400), spins.front() - friction * 0.4 / kWheelInertia, 0.01 * 6.4) << "at 0.4 s";
  for (size_t i = 900; i < spins.size(); ++i) ASSERT_NEAR(spins[i], 0, 1e-3) << "stopped, at step " << i;
}

INSTANTIATE_TEST_SUITE_P(WheelModels, RobotBodyActuation, ::testing::ValuesIn(test::kWheelModels));
INSTANTIATE_TEST_SUITE_P(OneRigidBody, RobotBodyActuation, ::testing::Values(kRigid));
INSTANTIATE_TEST_SUITE_P(WheelModels, FreeWheel, ::testing::ValuesIn(test::kWheelModels));

}  // namespace
}  // namespace bullet_sim
