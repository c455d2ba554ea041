// A base on four swivel casters whose forks are collision meshes (issue 30, B2: MiR 100 stood on its forks,
// its drive wheels 7 mm off the floor, and did not move). A moving mesh that collides by its hull must be the
// mesh's hull: Bullet's btShapeHull, fed a hull with its default 4 cm margin, grew the forks by 4 cm all
// round, and their bottoms, 3.4 cm above the floor, carried the robot. Forks as hulls (max_convex_parts 1, as
// without CoACD): every wheel rests on the floor, and the base drives at the commanded speed on either wheel
// model.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_support.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {
namespace {

constexpr double kRadius = 0.0625;  // [m] of every wheel; their axles are this high when they touch z = 0

std::string swivelCasterBase() { return test::readFile(test::fixture("contact/swivel_caster_base.urdf")); }

class SwivelCasterBase : public ::testing::TestWithParam<std::string> {};

TEST_P(SwivelCasterBase, StandsOnItsWheelsAndDrivesAtTheCommandedSpeed) {
  SimulationOptions options;
  options.limits.max_convex_parts = 1;  // the forks collide by their hulls
  Simulation simulation(test::emptyWorld(), options);
  const ModelSpec model = test::parseQuietly(test::withWheelModel(swivelCasterBase(), GetParam()), "base");
  Robot& robot = simulation.spawn("base", model, {});
  const RobotBody& body = robot.body();
  for (long k = std::lround(0.5 / simulation.stepSize()); k > 0; --k) simulation.step();  // settles
  for (const char* wheel : {"left_wheel", "right_wheel", "fl_caster", "br_caster"}) {
    EXPECT_NEAR(body.linkPose(wheel).translation().z(), kRadius, 0.002) << wheel << "'s axle";
  }

  // 0.5 m/s: after 1 s of spin-up, 2 s at v cover v * 2 s.
  WheeledDrive& drive = *test::pluginsOf<WheeledDrive>(robot).at(0);
  const double v = 0.5;
  double x0 = 0;
  const long second = std::lround(1.0 / simulation.stepSize());
  for (long k = 0; k < 3 * second; ++k) {
    if (k % 100 == 0) {
      ASSERT_TRUE(drive.setCommand(v, 0, simulation.time()));
    }
    if (k == second) x0 = body.linkPose("base_footprint").translation().x();
    simulation.step();
  }
  const Eigen::Vector3d end = body.linkPose("base_footprint").translation();
  EXPECT_NEAR(end.x() - x0, v * 2.0, 0.03 * v * 2.0);
  EXPECT_NEAR(end.y(), 0.0, 0.02);
}

INSTANTIATE_TEST_SUITE_P(WheelModels, SwivelCasterBase, ::testing::ValuesIn(test::kWheelModels),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace bullet_sim
