// Issue 28: contact never adds energy. With the motors off, E = sum over links of 1/2 m v^2 + 1/2 w^T I w +
// m g z, plus what the raycast suspension's springs hold (1/2 k x^2), sampled every step until the robot
// rests, never exceeds its start by more than 1/2 M (0.1 m/s)^2 (the contacts' push-out speed) + 1 %: robots
// dropped from 0.05 to 0.5 m, coasting into walls at up to 2 m/s, and 200 seeded random poses.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/simulation/world_api.h"
#include "contact_support.h"

namespace bullet_sim {
namespace {

constexpr double kPushOutSpeed = 0.1;  // [m/s] PhysicsOptions::max_correcting_velocity
constexpr double kRestSpeed = 0.01;    // [m/s]
constexpr double kRestTurn = 0.02;     // [rad/s]
constexpr double kLongest = 3.0;       // [s] of watching

/// The robots whose drive can be switched off (diff drive and skid steer): the look-alikes and three shipped.
std::vector<StrikeRobot> switchableRobots() {
  std::vector<StrikeRobot> robots = test::lookAlikes();
  const auto shipped = test::shippedRobots();
  robots.insert(robots.end(), shipped.begin(), shipped.begin() + 3);
  return robots;
}

/// The largest rise of the robot's energy above its value now, stepping until it rests (or kLongest), and
/// the allowance.
struct EnergyRise {
  double rise = 0, allowance = 0;
};

EnergyRise watchEnergy(Simulation& simulation, const std::string& name) {
  const WorldApi world(simulation);
  const Robot& robot = *simulation.robot(name);
  const double start = robotEnergy(robot, simulation.world().gravity);
  EnergyRise energy;
  energy.allowance =
      0.5 * robotMass(robot.body().spec()) * kPushOutSpeed * kPushOutSpeed + 0.01 * std::abs(start);
  double resting = 0;  // [s] since it last moved
  while (simulation.time() < kLongest && resting < 0.5) {
    simulation.step();
    energy.rise = std::max(energy.rise, robotEnergy(robot, simulation.world().gravity) - start);
    const EntityState state = world.modelState(name);
    const bool still = state.linear.norm() < kRestSpeed && state.angular.norm() < kRestTurn;
    resting = still ? resting + simulation.stepSize() : 0;
  }
  return energy;
}

SimulationOptions stepOf(double step) {
  SimulationOptions options;
  options.physics.step_size = step;
  return options;
}

TEST(ContactEnergy, ADroppedRobotGainsNone) {
  for (const StrikeRobot& robot : switchableRobots()) {
    for (const std::string& model : test::kWheelModels) {
      for (double step : {0.001, 0.01}) {
        for (double drop : {0.05, 0.2, 0.5}) {
          SCOPED_TRACE(robot.name + " " + model + " " + std::to_string(step) + " s from " +
                       std::to_string(drop) + " m");
          Simulation simulation(test::emptyWorld(), stepOf(step));
          WorldApi world(simulation);
          simulation.spawn(
              "robot", test::parseQuietly(withMotorsOff(withStrikeWheelModel(robot.urdf, model)), robot.name),
              {});
          EntityState lifted = world.modelState("robot");
          lifted.pose.translation().z() += drop;
          world.setModelState("robot", lifted);
          const EnergyRise energy = watchEnergy(simulation, "robot");
          EXPECT_LE(energy.rise, energy.allowance);
        }
      }
    }
  }
}

TEST(ContactEnergy, ARobotCoastingIntoAWallOrAnEdgeGainsNone) {
  for (const StrikeRobot& robot : switchableRobots()) {
    for (const std::string& model : test::kWheelModels) {
      for (double step : {0.001, 0.01}) {
        for (StrikeTarget target : {StrikeTarget::kWall, StrikeTarget::kDoorEdge}) {
          const StrikeCell cell{model, step, 2.0, 0, target, /*coast=*/true};
          const StrikeOutcome outcome = runStrike(robot, cell, test::emptyWorld());
          EXPECT_TRUE(outcome.reached) << cellName(robot, cell);
          EXPECT_LE(outcome.energy_gain, outcome.energy_allowance) << cellName(robot, cell);
        }
      }
    }
  }
}

/// A pose of `model` turned by `orientation` whose lowest collision point is `clearance` [m] above the
/// ground.
SpawnPose clearPose(const ModelSpec& model, const Eigen::Quaterniond& orientation, double clearance) {
  Eigen::Isometry3d turned = Eigen::Isometry3d::Identity();
  turned.linear() = orientation.toRotationMatrix();
  double lowest = std::numeric_limits<double>::infinity();
  const auto links = linkPosesAtZero(model);
  for (const auto& link : model.links) {
    for (const auto& collision : link.collisions)
      lowest =
          std::min(lowest, lowestPoint(collision.shape, turned * links.at(link.name) * collision.origin));
  }
  Diagnostics diagnostics("random pose");
  return spawnPoseFrom(Eigen::Vector3d(0, 0, clearance - lowest), orientation, false, diagnostics);
}

// 200 poses, each a robot, a wheel model, a step, a uniformly random attitude and a height of 0 to 0.3 m
// above the ground, seeded: each robot tumbles onto the ground with its motors off and comes to rest.
TEST(ContactEnergy, TwoHundredRandomPosesGainNone) {
  const std::vector<StrikeRobot> robots = switchableRobots();
  std::mt19937_64 generator(28);
  const auto uniform = [&](double low, double high) {  // portable, unlike std::uniform_real_distribution
    return low + (high - low) * static_cast<double>(generator() >> 11) * 0x1.0p-53;
  };
  for (int i = 0; i < 200; ++i) {
    const StrikeRobot& robot = robots[i % robots.size()];
    const std::string model = test::kWheelModels[(i / robots.size()) % 2];
    const double step = i % 3 == 0 ? 0.01 : 0.001;
    // A uniform rotation (Shoemake's method), then a height.
    const double u1 = uniform(0, 1), u2 = uniform(0, 2 * M_PI), u3 = uniform(0, 2 * M_PI);
    const Eigen::Quaterniond orientation(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                                         std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
    const ModelSpec spec =
        test::parseQuietly(withMotorsOff(withStrikeWheelModel(robot.urdf, model)), robot.name);
    Simulation simulation(test::emptyWorld(), stepOf(step));
    simulation.spawn("robot", spec, clearPose(spec, orientation, uniform(0.0, 0.3)));
    const EnergyRise energy = watchEnergy(simulation, "robot");
    EXPECT_LE(energy.rise, energy.allowance) << "pose " << i << ": " << robot.name << " " << model << " "
                                             << step << " s, attitude " << orientation.coeffs().transpose();
  }
}

}  // namespace
}  // namespace bullet_sim
