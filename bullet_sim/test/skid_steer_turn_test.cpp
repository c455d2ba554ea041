// Skid steering turning in place against Coulomb's rate (issue 29): four wheels at (+-a, +-b) whose rims turn
// at +-w b, each pressed with the same load and sliding with an isotropic friction cone, balance their yaw
// moments at w b^2 / (a^2 + b^2). A track wider than the wheelbase and one narrower, on the `raycast` model
// (the `contact` model does not hold it yet: docs/known_limitations.md).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "contact_support.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {
namespace {

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

/// The light skid-steer look-alike (wheels at x +-0.1, y +-0.125) with its wheels moved to (+-a, +-b).
std::string skidSteer(double a, double b) {
  std::string urdf = test::readFile(test::fixture("contact/light_skid_steer.urdf"));
  const std::string x = std::to_string(a), y = std::to_string(b);
  urdf = replaceAll(urdf, "0.1 0.125 0", x + " " + y + " 0");  // also turns -0.1 into -a
  urdf = replaceAll(urdf, "0.1 -0.125 0", x + " -" + y + " 0");
  urdf = replaceAll(urdf, "0.34 0.2 0.08", "0.34 " + std::to_string(2 * b - 0.05) + " 0.08");
  return replaceAll(urdf, "<wheelSeparation>0.25<", "<wheelSeparation>" + std::to_string(2 * b) + "<");
}

/// The yaw rate of the robot commanded to turn in place at `w`, once its wheels have spun up.
double turnRate(const std::string& urdf, const std::string& wheel_model, double w) {
  Simulation simulation(test::emptyWorld());
  Robot& robot = simulation.spawn("car", test::modelOf({"skid", urdf, ""}, wheel_model), {});
  WheeledDrive& drive = *test::pluginsOf<WheeledDrive>(robot).at(0);
  const auto yaw = [&] { return test::planar(robot.body().linkPose("base_footprint")).yaw; };
  const long steps = std::lround(1.0 / simulation.stepSize());
  double unwrapped = 0, last = 0, start = 0;
  for (long i = 0; i < 3 * steps; ++i) {
    if (i % 100 == 0) {
      EXPECT_TRUE(drive.setCommand(0, w, simulation.time()));
    }
    simulation.step();
    unwrapped += test::angleDifference(yaw(), last);
    last = yaw();
    if (i == steps) start = unwrapped;  // after one second: spun up
  }
  return (unwrapped - start) / 2.0;
}

void checkCoulombRate(double a, double b) {
  const double w = 1.0;
  const double coulomb = w * b * b / (a * a + b * b);
  SCOPED_TRACE("a " + std::to_string(a) + " m, b " + std::to_string(b) + " m");
  for (const std::string model : {"raycast", "contact"}) {
    EXPECT_NEAR(turnRate(skidSteer(a, b), model, w), coulomb, 0.05 * coulomb) << model;
  }
}

TEST(SkidSteerTurn, TrackWiderThanWheelbaseTurnsAtCoulombsRate) { checkCoulombRate(0.1, 0.125); }

TEST(SkidSteerTurn, TrackNarrowerThanWheelbaseTurnsAtCoulombsRate) { checkCoulombRate(0.15, 0.09); }

}  // namespace
}  // namespace bullet_sim
