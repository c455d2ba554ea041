// The multi-sensor test robot (test/fixtures/robots/multi_sensor_robot.urdf.xacro), and the URDF edits, load
// checks and drive commands the tests of its plugins share.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"
#include "plugins/planar_move/planar_move.h"
#include "test_support.h"

namespace bullet_sim::test {

inline const std::string kFixture = "test/fixtures/robots/multi_sensor_robot.urdf.xacro";

/// `urdf` with the tags of the plugin of sensor `sensor` set (or added).
inline std::string withSensorPluginTags(const std::string& urdf, const std::string& sensor,
                                        const Tags& tags) {
  return editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      for (auto* element = gazebo->FirstChildElement("sensor"); element;
           element = element->NextSiblingElement("sensor")) {
        if (sensor != element->Attribute("name")) continue;
        auto* plugin = element->FirstChildElement("plugin");
        for (const auto& [tag, text] : tags) {
          auto* child = plugin->FirstChildElement(tag.c_str());
          (child ? child : plugin->InsertNewChildElement(tag.c_str()))->SetText(text.c_str());
        }
        return;
      }
    }
    throw std::runtime_error("no sensor [" + sensor + "]");
  });
}

/// `urdf` without the tags `tags` of its model plugin `filename`.
inline std::string withoutPluginTags(const std::string& urdf, const std::string& filename,
                                     const std::vector<std::string>& tags) {
  return editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      auto* plugin = gazebo->FirstChildElement("plugin");
      if (!plugin || filename != plugin->Attribute("filename")) continue;
      for (const auto& tag : tags) plugin->DeleteChild(plugin->FirstChildElement(tag.c_str()));
    }
  });
}

/// The load warnings hector's plugins always give: their services and topics of hector's own types.
inline const std::vector<std::string> kHectorWarnings = {
    "need hector's own types, which Debian lacks: left out"};

/// Parses `urdf`; a load warning that contains none of `expected` fails the test.
inline ModelSpec parseExpecting(const std::string& urdf, const std::string& source,
                                const std::vector<std::string>& expected = kHectorWarnings) {
  std::vector<std::string> warnings;
  ModelSpec model = parseModel(urdf, source, PackageResolver::fromEnvironment(), &warnings);
  for (const auto& warning : warnings) {
    const bool known = std::any_of(expected.begin(), expected.end(), [&](const std::string& part) {
      return warning.find(part) != std::string::npos;
    });
    if (!known) ADD_FAILURE() << source << ": unexpected load warning: " << warning;
  }
  return model;
}

/// The load warnings of `urdf` (which must load).
inline std::vector<std::string> loadWarnings(const std::string& urdf) {
  std::vector<std::string> warnings;
  parseModel(urdf, "robot", PackageResolver::fromEnvironment(), &warnings);
  return warnings;
}

/// The load errors of `urdf`.
inline std::vector<std::string> loadErrors(const std::string& urdf) {
  try {
    parseModel(urdf, "robot", PackageResolver::fromEnvironment());
  } catch (const SpecError& error) {
    return error.problems();
  }
  return {};
}

/// The multi-sensor robot's URDF.
inline std::string multiSensorUrdf(const std::string& drive = "planar") {
  return expandXacro("bullet_sim", kFixture, {"drive:=" + drive});
}

/// The multi-sensor robot, with planar move ("planar") or force-based move ("force_based").
inline ModelSpec multiSensorRobot(const std::string& drive = "planar") {
  return parseExpecting(multiSensorUrdf(drive), "multi_sensor_robot");
}

/// A body-frame command: x, y [m/s] and the yaw rate [rad/s].
inline Twist twist(double x, double y, double yaw_rate) {
  Twist command;
  command.linear = {x, y, 0};
  command.angular = {0, 0, yaw_rate};
  return command;
}

/// Steps `seconds`, sending `command` to the robot's planar move every 0.1 s as `rostopic pub -r 10` does.
inline void drivePlanar(Simulation& simulation, PlanarMove& drive, const Twist& command, double seconds) {
  stepSending(simulation, seconds, [&] { return drive.setCommand(command, simulation.time()); });
}

/// The plugin of type T named `name` (its sensor's name for a sensor's plugin).
template <class T>
T& pluginNamed(const Robot& robot, const std::string& name) {
  for (T* plugin : test::pluginsOf<T>(robot)) {
    if (plugin->name() == name) return *plugin;
  }
  throw std::runtime_error("no plugin [" + name + "]");
}

}  // namespace bullet_sim::test
