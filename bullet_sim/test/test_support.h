// Helpers shared by the core's tests: expanding the shipped robots and finding shipped files.
#pragma once

#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "bullet_sim/model/model.h"
#include "bullet_sim/assets/package_resolver.h"
#include "bullet_sim/model/world.h"
#include "bullet_sim/plugins/registry.h"
#include "plugins/ros_control/controller_manager.h"
#include "bullet_sim/simulation/simulation.h"
#include "bullet_sim/tools/subprocess.h"

namespace bullet_sim::test {

using CommandResult = ProcessOutput;

/// A folder of its own under the system's temporary folder, made at once and removed with all it holds.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "bullet_sim_test_XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TemporaryFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The plugins of concrete type T (e.g. WheeledDrive, RayLidar) of a robot: for tests of that plugin, which
/// may look inside it. Everyone else reads a robot's typed outputs (Robot::outputs).
template <class T>
std::vector<T*> pluginsOf(const Robot& robot) {
  std::vector<T*> found;
  for (const auto& plugin : robot.plugins()) {
    if (auto* typed = dynamic_cast<T*>(plugin.get())) found.push_back(typed);
  }
  return found;
}

/// The stream of `plugin`'s output of `Sample`s on `topic` (relative to its namespace), or of its first
/// output of that type when `topic` is "" (a camera's colour image before its depth image); throws when there
/// is none.
template <class Sample>
const Stream<Sample>& streamOf(const Plugin& plugin, const std::string& topic = "") {
  for (const OutputPort& port : plugin.ports().outputs) {
    const auto* stream = std::get_if<const Stream<Sample>*>(&port.stream);
    if (stream && (topic.empty() || port.topic == topic)) return **stream;
  }
  throw std::runtime_error("plugin [" + plugin.name() + "] has no such output [" + topic + "]");
}

/// The latest sample of `plugin`'s output (streamOf).
template <class Sample>
const Sample& latestOf(const Plugin& plugin, const std::string& topic = "") {
  return streamOf<Sample>(plugin, topic).latest();
}

/// How many samples `plugin`'s output (streamOf) published.
template <class Sample>
uint64_t countOf(const Plugin& plugin, const std::string& topic = "") {
  return streamOf<Sample>(plugin, topic).count();
}

/// Steps `seconds` of sim time, calling `send()` every 0.1 s from the first step, as `rostopic pub -r 10`
/// sends; `send` returns whether its command was taken, and a refusal fails the test.
template <class Send>
void stepSending(Simulation& simulation, double seconds, Send send) {
  const auto steps = std::lround(seconds / simulation.stepSize());
  const auto resend = std::lround(0.1 / simulation.stepSize());
  for (long i = 0; i < steps; ++i) {
    if (i % resend == 0) {
      ASSERT_TRUE(send());
    }
    simulation.step();
  }
}

/// Runs a shell command line, as a user would type it; its exit status, stdout and stderr.
inline CommandResult run(const std::string& command) {
  std::string error;
  const auto result = runProcess({"/bin/sh", "-c", command}, &error);
  if (!result) throw std::runtime_error(error);
  return *result;
}

/// A file shipped in `package`, found through ROS_PACKAGE_PATH.
inline std::string packageFile(const std::string& package, const std::string& relative) {
  const auto dir = PackageResolver::fromEnvironment().packageDirectory(package);
  if (!dir) throw std::runtime_error("package [" + package + "] is not in ROS_PACKAGE_PATH");
  return *dir + "/" + relative;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read [" + path + "]");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The URDF of a shipped xacro; each expansion (about 0.3 s) runs once per test binary.
inline std::string expandXacro(const std::string& package, const std::string& xacro,
                               const std::vector<std::string>& args = {}) {
  static std::map<std::string, std::string> expanded;
  std::string key = package + "/" + xacro;
  for (const auto& arg : args) key += " " + arg;
  auto found = expanded.find(key);
  if (found != expanded.end()) return found->second;
  return expanded[key] = bullet_sim::expandXacro(packageFile(package, xacro), args);
}

using Tags = std::vector<std::pair<std::string, std::string>>;  ///< tag name, text

/// Edits a URDF's XML with tinyxml2: `edit` gets its <robot> element.
template <class Edit>
std::string editUrdf(const std::string& urdf, Edit edit) {
  tinyxml2::XMLDocument document;
  if (document.Parse(urdf.c_str(), urdf.size()) != tinyxml2::XML_SUCCESS || !document.RootElement())
    throw std::runtime_error("not XML: " + std::string(document.ErrorStr()));
  edit(*document.RootElement());
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

/// `urdf` with one more model plugin, <gazebo><plugin name filename> holding `tags`.
inline std::string withPlugin(const std::string& urdf, const std::string& name, const std::string& filename,
                              const Tags& tags) {
  return editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    auto* plugin = robot.InsertNewChildElement("gazebo")->InsertNewChildElement("plugin");
    plugin->SetAttribute("name", name.c_str());
    plugin->SetAttribute("filename", filename.c_str());
    for (const auto& [tag, text] : tags) plugin->InsertNewChildElement(tag.c_str())->SetText(text.c_str());
  });
}

/// `urdf` with the tags of every model plugin whose filename ends with `filename_end` set (or added).
inline std::string withPluginTags(const std::string& urdf, const std::string& filename_end,
                                  const Tags& tags) {
  return editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    int found = 0;
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      for (auto* plugin = gazebo->FirstChildElement("plugin"); plugin;
           plugin = plugin->NextSiblingElement("plugin")) {
        const std::string filename = plugin->Attribute("filename") ? plugin->Attribute("filename") : "";
        if (filename.size() < filename_end.size() ||
            filename.compare(filename.size() - filename_end.size(), filename_end.size(), filename_end) != 0)
          continue;
        ++found;
        for (const auto& [tag, text] : tags) {
          auto* element = plugin->FirstChildElement(tag.c_str());
          (element ? element : plugin->InsertNewChildElement(tag.c_str()))->SetText(text.c_str());
        }
      }
    }
    if (found == 0) throw std::runtime_error("no plugin [*" + filename_end + "] to edit");
  });
}

/// `urdf` with its drive plugin asking for `wheel_model` ("contact" or "raycast"; "" leaves it as it is).
inline std::string withWheelModel(const std::string& urdf, const std::string& wheel_model) {
  return wheel_model.empty() ? urdf : withPluginTags(urdf, "_drive.so", {{"wheelModel", wheel_model}});
}

/// Parses a URDF as the simulator does; a load warning fails the test, since the files tests load are clean
/// unless a test says otherwise (MuJoCo's habit).
inline ModelSpec parseQuietly(const std::string& urdf, const std::string& source) {
  std::vector<std::string> warnings;
  ModelSpec model = parseModel(urdf, source, PackageResolver::fromEnvironment(), &warnings);
  for (const auto& warning : warnings) ADD_FAILURE() << source << ": unexpected load warning: " << warning;
  return model;
}

inline ModelSpec loadShippedRobot(const std::string& package, const std::string& xacro,
                                  const std::string& wheel_model = "") {
  return parseQuietly(withWheelModel(expandXacro(package, xacro), wheel_model), package + "/" + xacro);
}

inline ModelSpec wheelchair(const std::string& wheel_model = "") {
  return loadShippedRobot("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro", wheel_model);
}
inline ModelSpec smartcar(const std::string& wheel_model = "") {
  return loadShippedRobot("smartcar_description", "urdf/smartcar.urdf.xacro", wheel_model);
}
inline ModelSpec yahboomcar(const std::string& wheel_model = "") {
  return loadShippedRobot("yahboomcar_description", "urdf/yahboomcar.urdf.xacro", wheel_model);
}

/// Every wheel model; the behaviour tests run against each.
inline const std::vector<std::string> kWheelModels = {"contact", "raycast"};

inline WorldSpec shippedWorld(const std::string& name) {
  return loadWorld(packageFile("bullet_sim", "worlds/" + name), PackageResolver::fromEnvironment(), nullptr);
}

inline std::string fixture(const std::string& relative) {
  return packageFile("bullet_sim", "test/fixtures/" + relative);
}

/// The two-joint trajectory arm (fixtures/robots/trajectory_arm.urdf) with its transmissions on `interface`
/// ("PositionJointInterface", "EffortJointInterface", ...), parsed.
inline ModelSpec trajectoryArm(const std::string& interface) {
  const std::string arm = readFile(fixture("robots/trajectory_arm.urdf"));
  const std::string urdf = editUrdf(arm, [&](tinyxml2::XMLElement& robot) {
    for (auto* t = robot.FirstChildElement("transmission"); t; t = t->NextSiblingElement("transmission"))
      t->FirstChildElement("joint")->FirstChildElement("hardwareInterface")->SetText(
          ("hardware_interface/" + interface).c_str());
  });
  return parseQuietly(urdf, "trajectory_arm.urdf");
}

/// two_wheeler.urdf with a diff drive named "drive" on its wheels, and `more` tags for it.
inline std::string twoWheelerWithDiffDrive(const Tags& more = {}) {
  Tags tags = {{"leftJoint", "left_wheel_joint"},
               {"rightJoint", "right_wheel_joint"},
               {"wheelSeparation", "0.35"},
               {"wheelDiameter", "0.1"}};
  tags.insert(tags.end(), more.begin(), more.end());
  return withPlugin(readFile(fixture("robots/two_wheeler.urdf")), "drive", "libgazebo_ros_diff_drive.so",
                    tags);
}

/// Replaces the first `from` after `anchor` in `text`; fails the test when either is missing.
inline std::string replaceAfter(std::string text, const std::string& anchor, const std::string& from,
                                const std::string& to) {
  const auto at = text.find(anchor);
  EXPECT_NE(at, std::string::npos) << anchor;
  const auto found = text.find(from, at);
  EXPECT_NE(found, std::string::npos) << from;
  if (at != std::string::npos && found != std::string::npos) text.replace(found, from.size(), to);
  return text;
}

/// A pose on the floor: x [m], y [m] and yaw [rad].
struct Planar {
  double x, y, yaw;
};

inline Planar planar(const Eigen::Isometry3d& pose) {
  return {pose.translation().x(), pose.translation().y(),
          std::atan2(pose.linear()(1, 0), pose.linear()(0, 0))};
}

/// a - b, wrapped into [-pi, pi] [rad].
inline double angleDifference(double a, double b) { return std::remainder(a - b, 2 * M_PI); }

/// Steps until `done()` holds, for at most `max_seconds` of sim time; false, with a test failure naming
/// `what`, when it never does.
template <class Done>
bool stepUntil(Simulation& simulation, Done done, double max_seconds, const std::string& what) {
  const double deadline = simulation.time() + max_seconds;
  while (!done()) {
    if (simulation.time() >= deadline) {
      ADD_FAILURE() << what << " did not happen within " << max_seconds << " s of sim time";
      return false;
    }
    simulation.step();
  }
  return true;
}

/// Loads `names` on `manager` and starts them at `time` [s] in one STRICT switch, as controller_manager's
/// spawner does; fails the test when either is refused.
inline void startControllers(ControllerManager& manager, const std::vector<std::string>& names, double time) {
  for (const auto& name : names) ASSERT_EQ(manager.load(name, nullptr), "") << name;
  SwitchControllerRequest start;
  start.start = names;
  start.strictness = SwitchControllerRequest::kStrict;
  ASSERT_EQ(manager.switchControllers(start, time, nullptr), "");
}

}  // namespace bullet_sim::test
