// What the contact tests share (issue 28): the robots they strike, drop and bury, the shipped ones and the
// look-alikes of common public shapes under test/fixtures/contact/.
#pragma once

#include <cctype>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_sim/tools/strike_matrix.h"
#include "test_support.h"

namespace bullet_sim::test {

/// A look-alike: "caster_two_wheeler", "light_skid_steer" or "tall_base".
inline StrikeRobot lookAlike(const std::string& name) {
  return {name, readFile(fixture("contact/" + name + ".urdf")), ""};
}

inline std::vector<StrikeRobot> lookAlikes() {
  return {lookAlike("caster_two_wheeler"), lookAlike("light_skid_steer"), lookAlike("tall_base")};
}

/// The shipped robots that drive through a drive plugin (the rover drives through ros_control).
inline std::vector<StrikeRobot> shippedRobots() {
  return {{"wheelchair", expandXacro("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro"), ""},
          {"smartcar", expandXacro("smartcar_description", "urdf/smartcar.urdf.xacro"), ""},
          {"yahboomcar", expandXacro("yahboomcar_description", "urdf/yahboomcar.urdf.xacro"), ""},
          {"tianracer", expandXacro("tianracer_description", "urdf/tianracer.urdf.xacro"), ""},
          {"rover", expandXacro("rover_description", "urdf/rover.urdf.xacro"),
           readFile(packageFile("rover_description", "config/control.yaml"))}};
}

/// `robot`'s description on `wheel_model` ("contact", "raycast"), parsed.
inline ModelSpec modelOf(const StrikeRobot& robot, const std::string& wheel_model) {
  return parseQuietly(withStrikeWheelModel(robot.urdf, wheel_model), robot.name);
}

/// Every failure of a strike, and the bounds it was judged by, for the test's message.
inline std::string describe(const StrikeOutcome& outcome) {
  const StrikeBounds& b = outcome.bounds;
  std::ostringstream text;
  for (const auto& failure : outcome.failures) text << failure << "; ";
  text << "tilt " << outcome.max_tilt << " rad, rise " << outcome.rise << " m, path " << outcome.path
       << " of " << outcome.command_path << " m; bounds: impact " << b.impact_energy << " J against "
       << b.barrier << " J (tips at " << b.tip_speed << " m/s: " << b.impact_tips << "), stall "
       << b.push * b.contact_height << " N m against " << b.mass * 9.81 * b.rear << " N m ("
       << b.stall_tips << "), climb ratio " << b.climb_ratio << ", h " << b.com_height << " m, z_c "
       << b.contact_height << " m";
  return text.str();
}

inline const WorldSpec& emptyWorld() {
  static const WorldSpec world = shippedWorld("empty.world");
  return world;
}

/// One strike of one robot.
struct StrikeCase {
  StrikeRobot robot;
  StrikeCell cell;
};

inline std::string caseName(const ::testing::TestParamInfo<StrikeCase>& info) {
  std::string name = cellName(info.param.robot, info.param.cell);
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

/// Per robot, wheel model and step: head-on into the wall at 0.5 m/s, into the door's edge at 30 degrees at
/// 2 m/s, and (at 10 ms, where a step covers 2 cm) into the 2 cm panel at 2 m/s.
inline std::vector<StrikeCase> representativeCells(const std::vector<StrikeRobot>& robots) {
  std::vector<StrikeCase> cases;
  for (const auto& robot : robots) {
    for (const std::string& model : kWheelModels) {
      for (double step : {0.001, 0.01}) {
        cases.push_back({robot, {model, step, 0.5, 0, StrikeTarget::kWall}});
        cases.push_back({robot, {model, step, 2.0, M_PI / 6, StrikeTarget::kDoorEdge}});
        if (step > 0.005) cases.push_back({robot, {model, step, 2.0, 0, StrikeTarget::kPanel}});
      }
    }
  }
  return cases;
}

/// Runs the strike, prints its figures and both bounds, and expects it to meet the target within them.
inline void expectWithinBounds(const StrikeRobot& robot, const StrikeCell& cell) {
  const StrikeOutcome outcome = runStrike(robot, cell, emptyWorld());
  std::cout << cellName(robot, cell) << ": " << describe(outcome) << "\n";
  EXPECT_TRUE(outcome.reached);
  EXPECT_TRUE(outcome.passed()) << describe(outcome);
}

}  // namespace bullet_sim::test
