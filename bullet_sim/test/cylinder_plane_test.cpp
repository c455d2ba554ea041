// A cylinder on the ground plane touches it as a cylinder does (issue 29): lying down, on its tread, level
// and still; standing, on the rim of its lower end.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "contact_support.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {
namespace {

constexpr double kRadius = 0.05, kLength = 0.04, kMass = 0.5;  // a wheel's size [m] and mass [kg]

/// A free cylinder whose axis lies along y (`lying`) or stands along z, resting on the ground.
std::string cylinderUrdf(bool lying) {
  const std::string rpy = lying ? "1.5707963267948966 0 0" : "0 0 0";
  const std::string z = std::to_string(lying ? kRadius : kLength / 2);
  return "<robot name='can'><link name='can'><inertial><origin xyz='0 0 " + z + "'/><mass value='" +
         std::to_string(kMass) + "'/><inertia ixx='1e-3' iyy='1e-3' izz='1e-3' ixy='0' ixz='0' iyz='0'/>" +
         "</inertial><collision><origin xyz='0 0 " + z + "' rpy='" + rpy + "'/><geometry><cylinder radius='" +
         std::to_string(kRadius) + "' length='" + std::to_string(kLength) +
         "'/></geometry></collision></link></robot>";
}

struct Resting {
  std::vector<ContactPoint> points;  ///< where it touches the ground, in its link's frame
  double end_drop = 0;               ///< [m] of one end of its axis below the other
  double speed = 0;                  ///< [m/s] of its link's origin
};

/// The cylinder after 2 s at rest.
Resting restAt(bool lying) {
  Simulation simulation(test::emptyWorld());
  Robot& robot = simulation.spawn("can", test::parseQuietly(cylinderUrdf(lying), "can"), {});
  for (int i = 0; i < 2000; ++i) simulation.step();
  Resting resting;
  const Eigen::Isometry3d pose = robot.body().linkPose("can");
  for (const auto& contact : robot.body().contacts({"can", 0})) {
    for (ContactPoint point : contact.points) {
      point.position = pose.inverse() * point.position;
      resting.points.push_back(point);
    }
  }
  const Eigen::Vector3d axis = pose.linear() * (lying ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ());
  resting.end_drop = lying ? std::abs(axis.z()) * kLength : 0.0;
  resting.speed = robot.body().linkLinearVelocity("can").norm();
  return resting;
}

TEST(CylinderPlane, ALyingCylinderRestsLevelOnItsTread) {
  const Resting resting = restAt(true);
  ASSERT_FALSE(resting.points.empty());
  double total = 0;
  for (const auto& point : resting.points) {
    EXPECT_LE(std::abs(point.position.y()), kLength / 2 + 1e-6);  // on the tread
    EXPECT_NEAR(point.position.z(), 0, 1e-3);                      // at the bottom
    total += point.force.z();
  }
  EXPECT_NEAR(total, kMass * 9.81, 0.02 * kMass * 9.81);
  EXPECT_LT(resting.end_drop, 1e-3);  // level: one end at most 1 mm below the other
  EXPECT_LT(resting.speed, 1e-3);     // and still
}

TEST(CylinderPlane, AStandingCylinderRestsOnTheRimOfItsLowerEnd) {
  const auto points = restAt(false).points;
  ASSERT_EQ(points.size(), 4u);
  double total = 0;
  for (const auto& point : points) {
    EXPECT_NEAR(point.position.head<2>().norm(), kRadius, 1e-3);
    EXPECT_NEAR(point.position.z(), 0, 1e-3);
    total += point.force.z();
  }
  EXPECT_NEAR(total, kMass * 9.81, 0.02 * kMass * 9.81);
}

}  // namespace
}  // namespace bullet_sim
