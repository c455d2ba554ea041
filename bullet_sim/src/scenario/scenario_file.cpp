#include "bullet_sim/scenario/scenario_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/world.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

constexpr double kMaxDuration = 24 * 3600;  // [s] of sim time
constexpr int kMaxRobots = 100;
constexpr int kMaxCells = 1000000;

/// Reads YAML nodes into typed values, collecting every problem with the key path it is at.
class Reader {
 public:
  Reader(std::string source, const PackageResolver& resolver)
      : source_(std::move(source)), resolver_(resolver) {}

  void error(const std::string& path, const std::string& message) {
    errors_.push_back(path + ": " + message);
  }
  void throwIfErrors() const {
    if (errors_.empty()) return;
    std::string text = "scenario " + source_ + ":";
    for (const auto& error : errors_) text += "\n  " + error;
    throw ScenarioError(text);
  }

  /// Reports the keys of `map` that are not in `known`; false when `map` is not a mapping.
  bool keys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& known) {
    if (!map.IsMap()) {
      error(path, "expected a mapping of " + list(known));
      return false;
    }
    for (const auto& entry : map) {
      const std::string key = entry.first.as<std::string>();
      if (std::find(known.begin(), known.end(), key) == known.end())
        error(join(path, key), "unknown key" + didYouMean(key, known) + "; expected one of " + list(known));
    }
    return true;
  }

  /// A number in [low, high], or `fallback` when the key is absent.
  double number(const YAML::Node& map, const std::string& key, const std::string& path, double fallback,
                double low = -1e12, double high = 1e12) {
    const YAML::Node node = map[key];
    if (!node) return fallback;
    double value = NAN;
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      error(join(path, key), "[" + text(node) + "] is not a number");
      return fallback;
    }
    if (!std::isfinite(value) || value < low || value > high) {
      std::ostringstream range;
      range << "[" << text(node) << "] is out of range: give a number from " << low << " to " << high;
      error(join(path, key), range.str());
      return fallback;
    }
    return value;
  }

  std::string string(const YAML::Node& map, const std::string& key, const std::string& path,
                     const std::string& fallback = "") {
    const YAML::Node node = map[key];
    if (!node) return fallback;
    if (!node.IsScalar()) {
      error(join(path, key), "expected a single value, not [" + text(node) + "]");
      return fallback;
    }
    return node.as<std::string>();
  }

  /// A file named in the scenario: absolute, $(find pkg)/..., package://..., or relative to the scenario's
  /// folder. "" (with an error) when it does not exist.
  std::string file(const std::string& name, const std::string& path) {
    const std::string resolved = resolvePath(name, path);
    std::error_code ec;
    if (resolved.empty()) return "";
    if (!fs::is_regular_file(resolved, ec)) {
      error(path,
            "[" + name + "] is not a file" + (resolved != name ? " (" + resolved + ")" : std::string()));
      return "";
    }
    return resolved;
  }

  std::string resolvePath(const std::string& name, const std::string& path) {
    static const std::string find = "$(find ";
    if (name.rfind(find, 0) == 0) {
      const size_t close = name.find(')');
      const std::string package =
          name.substr(find.size(), close == std::string::npos ? 0 : close - find.size());
      const auto directory = resolver_.packageDirectory(package);
      if (!directory) {
        error(path,
              "[" + name + "]: no package [" + package + "] on ROS_PACKAGE_PATH (source devel/setup.bash)");
        return "";
      }
      return *directory + name.substr(close + 1);
    }
    std::string message;
    const auto resolved = resolver_.resolve(name, &message);
    if (!resolved) {
      error(path, message);
      return "";
    }
    const fs::path file(*resolved);
    return file.is_absolute() ? file.string() : (folder() / file).lexically_normal().string();
  }

  fs::path folder() const { return fs::absolute(fs::path(source_)).parent_path(); }
  const PackageResolver& resolver() const { return resolver_; }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }
  static std::string text(const YAML::Node& node) {
    YAML::Emitter out;
    out << YAML::Flow << node;
    return out.c_str();
  }

 private:
  static std::string list(const std::vector<std::string>& names) {
    std::string text;
    for (const auto& name : names) text += (text.empty() ? "[" : ", [") + name + "]";
    return text;
  }

  std::string source_;
  const PackageResolver& resolver_;
  std::vector<std::string> errors_;
};

void readRobot(Reader& reader, const YAML::Node& robot, ScenarioSpec& spec) {
  if (!robot) return reader.error("robot", "missing: give robot.description, a URDF or xacro file");
  if (!reader.keys(robot, "robot", {"description", "args", "name", "count", "wheel_model"})) return;
  const std::string description = reader.string(robot, "description", "robot");
  if (description.empty()) reader.error("robot.description", "missing: give a URDF or xacro file");
  else spec.description = reader.file(description, "robot.description");
  if (const YAML::Node args = robot["args"]) {
    if (!args.IsMap()) reader.error("robot.args", "expected a mapping of xacro arguments, name: value");
    else
      for (const auto& arg : args)
        spec.xacro_args.push_back(arg.first.as<std::string>() + ":=" + Reader::text(arg.second));
  }
  spec.robot_name = reader.string(robot, "name", "robot");
  spec.count = static_cast<int>(reader.number(robot, "count", "robot", 1, 1, kMaxRobots));
  if (robot["count"] && reader.number(robot, "count", "robot", 1) != spec.count)
    reader.error("robot.count", "give a whole number");
  if (robot["wheel_model"]) {
    spec.wheel_model = reader.string(robot, "wheel_model", "robot");
    if (*spec.wheel_model != "raycast" && *spec.wheel_model != "contact")
      reader.error("robot.wheel_model", "[" + *spec.wheel_model + "]: choose raycast or contact");
  }
}

SpawnPose readPose(Reader& reader, const YAML::Node& node, const std::string& path) {
  SpawnPose pose;
  if (!reader.keys(node, path, {"x", "y", "z", "yaw", "roll", "pitch", "joints"})) return pose;
  pose.x = reader.number(node, "x", path, 0);
  pose.y = reader.number(node, "y", path, 0);
  pose.yaw = reader.number(node, "yaw", path, 0);
  pose.roll = reader.number(node, "roll", path, 0);
  pose.pitch = reader.number(node, "pitch", path, 0);
  if (node["z"]) pose.z = reader.number(node, "z", path, 0);
  if (const YAML::Node joints = node["joints"]) {
    if (!joints.IsMap()) return reader.error(path + ".joints", "expected joint: position"), pose;
    for (const auto& joint : joints)
      pose.joints[joint.first.as<std::string>()] =
          reader.number(joints, joint.first.as<std::string>(), path + ".joints", 0);
  }
  return pose;
}

void readSpawn(Reader& reader, const YAML::Node& spawn, ScenarioSpec& spec) {
  if (!spawn) {
    spec.spawn.assign(1, SpawnPose{});
  } else if (spawn.IsMap()) {
    spec.spawn.push_back(readPose(reader, spawn, "spawn"));
  } else if (spawn.IsSequence()) {
    for (size_t i = 0; i < spawn.size(); ++i)
      spec.spawn.push_back(readPose(reader, spawn[i], "spawn." + std::to_string(i)));
  } else {
    reader.error("spawn", "expected a pose {x, y, yaw} or a list of them, one per robot");
  }
  if (spec.spawn.size() == 1 && spec.count > 1) {
    reader.error("spawn", "robot.count is " + std::to_string(spec.count) + ": give a list of as many poses");
  } else if (static_cast<int>(spec.spawn.size()) != spec.count && !spec.spawn.empty() && spawn &&
             spawn.IsSequence()) {
    reader.error("spawn", "has " + std::to_string(spec.spawn.size()) + " poses for robot.count " +
                              std::to_string(spec.count) + ": give one per robot");
  }
}

void readTimeline(Reader& reader, const YAML::Node& timeline, ScenarioSpec& spec) {
  if (!timeline.IsSequence()) return reader.error("drive.timeline", "expected a list of {duration, v, w}");
  for (size_t i = 0; i < timeline.size(); ++i) {
    const std::string path = "drive.timeline." + std::to_string(i);
    const YAML::Node segment = timeline[i];
    if (!reader.keys(segment, path, {"duration", "v", "vy", "w", "robot"})) continue;
    if (!segment["duration"]) reader.error(path, "missing duration [s]");
    TimelineSegment read;
    read.duration = reader.number(segment, "duration", path, 0, 0, kMaxDuration);
    read.v = reader.number(segment, "v", path, 0);
    read.vy = reader.number(segment, "vy", path, 0);
    read.w = reader.number(segment, "w", path, 0);
    read.robot = reader.string(segment, "robot", path);
    spec.timeline.push_back(read);
  }
}

void readLaunch(Reader& reader, const YAML::Node& launch, ScenarioSpec& spec) {
  const std::string path = "drive.launch";
  if (!reader.keys(launch, path, {"file", "args", "wait_for", "ready_timeout", "real_time_factor"})) return;
  LaunchDrive drive;
  const std::string file = reader.string(launch, "file", path);
  if (file.empty()) reader.error(path + ".file", "missing: give the launch file of your nodes");
  else drive.file = reader.file(file, path + ".file");
  if (const YAML::Node args = launch["args"]) {
    if (!args.IsMap()) reader.error(path + ".args", "expected a mapping of launch arguments, name: value");
    else
      for (const auto& arg : args)
        drive.args.emplace_back(arg.first.as<std::string>(), arg.second.as<std::string>());
  }
  if (const YAML::Node topics = launch["wait_for"]) {
    if (!topics.IsSequence()) reader.error(path + ".wait_for", "expected a list of topics");
    else
      for (const auto& topic : topics) drive.wait_for.push_back(topic.as<std::string>());
  }
  drive.ready_timeout = reader.number(launch, "ready_timeout", path, drive.ready_timeout, 0.1, 3600);
  drive.real_time_factor = reader.number(launch, "real_time_factor", path, drive.real_time_factor, 0, 1000);
  spec.launch = drive;
}

void readDrive(Reader& reader, const YAML::Node& drive, ScenarioSpec& spec) {
  if (!drive) return;  // the robots stand still
  if (!reader.keys(drive, "drive", {"timeline", "launch"})) return;
  if (drive["timeline"] && drive["launch"])
    return reader.error("drive", "give a timeline or a launch file, not both");
  if (drive["timeline"]) readTimeline(reader, drive["timeline"], spec);
  if (drive["launch"]) readLaunch(reader, drive["launch"], spec);
}

/// [low, high] from a two-number list.
bool readRange(Reader& reader, const YAML::Node& node, const std::string& path, double* low, double* high) {
  if (!node.IsSequence() || node.size() != 2) {
    reader.error(path, "expected [low, high]");
    return false;
  }
  YAML::Node pair;
  pair["low"] = node[0];
  pair["high"] = node[1];
  *low = reader.number(pair, "low", path, 0);
  *high = reader.number(pair, "high", path, 0);
  if (*low > *high) reader.error(path, "low is above high");
  return true;
}

void readReach(Reader& reader, const YAML::Node& node, const std::string& path, Check& check) {
  if (!reader.keys(node, path, {"x", "y", "radius", "by", "robot"})) return;
  check.by = reader.number(node, "by", path, NAN, 0, kMaxDuration);
  if (!node["by"]) reader.error(path, "missing by [s]: the sim time the region must be reached by");
  if (node["x"] && node["x"].IsSequence()) {
    readRange(reader, node["x"], path + ".x", &check.region.x_min, &check.region.x_max);
    if (!node["y"]) reader.error(path, "a box needs y: [low, high] as well");
    else readRange(reader, node["y"], path + ".y", &check.region.y_min, &check.region.y_max);
    if (node["radius"]) reader.error(path + ".radius", "a box [x range, y range] has no radius");
    return;
  }
  if (!node["x"] || !node["y"] || !node["radius"])
    reader.error(path, "give a circle x, y, radius [m] or a box x: [low, high], y: [low, high]");
  check.region.x = reader.number(node, "x", path, 0);
  check.region.y = reader.number(node, "y", path, 0);
  check.region.radius = reader.number(node, "radius", path, 1, 1e-6, 1e6);
}

void readClearance(Reader& reader, const YAML::Node& node, const std::string& path, Check& check) {
  if (!reader.keys(node, path, {"min", "from", "robot"})) return;
  if (!node["min"]) reader.error(path, "missing min [m]");
  check.min = reader.number(node, "min", path, 0, 0, 1e3);
  const std::string from = reader.string(node, "from", path, "geometry");
  if (from != "geometry" && from != "lidar")
    reader.error(path + ".from", "[" + from + "]: choose geometry or lidar");
  check.from_lidar = from == "lidar";
}

void readFinalPose(Reader& reader, const YAML::Node& node, const std::string& path, Check& check) {
  if (!reader.keys(node, path, {"x", "y", "yaw", "position_tolerance", "yaw_tolerance", "robot"})) return;
  if (!node["x"] || !node["y"] || !node["position_tolerance"])
    reader.error(path, "give x, y and position_tolerance [m] (and yaw, yaw_tolerance [rad])");
  check.x = reader.number(node, "x", path, 0);
  check.y = reader.number(node, "y", path, 0);
  check.position_tolerance = reader.number(node, "position_tolerance", path, 0, 0, 1e6);
  check.check_yaw = static_cast<bool>(node["yaw"]);
  if (check.check_yaw != static_cast<bool>(node["yaw_tolerance"]))
    reader.error(path, "give yaw and yaw_tolerance [rad] together");
  check.yaw = reader.number(node, "yaw", path, 0);
  check.yaw_tolerance = reader.number(node, "yaw_tolerance", path, 0, 0, M_PI);
}

Check readCheck(Reader& reader, const YAML::Node& item, const std::string& path) {
  static const std::vector<std::string> kTypes = {"reach",   "clearance",  "no_collision",
                                                  "upright", "final_pose", "no_load_warnings"};
  Check check;
  if (!item.IsMap() || item.size() != 1) {
    reader.error(path, "expected one check, e.g. {reach: {x: 2, y: 0, radius: 0.3, by: 8}}");
    return check;
  }
  const std::string type = item.begin()->first.as<std::string>();
  const YAML::Node node =
      item.begin()->second.IsNull() ? YAML::Node(YAML::NodeType::Map) : item.begin()->second;
  const std::string at = path + "." + type;
  const auto found = std::find(kTypes.begin(), kTypes.end(), type);
  if (found == kTypes.end()) {
    reader.error(path, "unknown check [" + type + "]" + didYouMean(type, kTypes));
    return check;
  }
  check.type = static_cast<Check::Type>(found - kTypes.begin());
  switch (check.type) {
    case Check::Type::kReach: readReach(reader, node, at, check); break;
    case Check::Type::kClearance: readClearance(reader, node, at, check); break;
    case Check::Type::kUpright:
      if (reader.keys(node, at, {"max_tilt", "robot"}))
        check.max_tilt = reader.number(node, "max_tilt", at, 0.2, 0, M_PI);
      break;
    case Check::Type::kFinalPose: readFinalPose(reader, node, at, check); break;
    case Check::Type::kNoCollision:
    case Check::Type::kNoLoadWarnings: reader.keys(node, at, {"robot"}); break;
  }
  if (node.IsMap()) check.robot = reader.string(node, "robot", at);
  return check;
}

void readVideo(Reader& reader, const YAML::Node& video, ScenarioSpec& spec) {
  if (!video || !reader.keys(video, "video", {"fps", "size"})) return;
  spec.video_fps = reader.number(video, "fps", "video", spec.video_fps, 1, 240);
  const std::string size = reader.string(video, "size", "video", "640x480");
  int width = 0, height = 0;
  char x = 0;
  std::istringstream in(size);
  if (!(in >> width >> x >> height) || x != 'x' || width < 16 || height < 16 || width > 4096 ||
      height > 4096 || width % 2 || height % 2) {
    return reader.error("video.size", "[" + size + "]: write WxH, even numbers from 16 to 4096");
  }
  spec.video_width = width;
  spec.video_height = height;
}

std::string readWorld(Reader& reader, const YAML::Node& root) {
  const std::string name = reader.string(root, "world", "", "empty.world");
  std::error_code ec;
  if (name.rfind("$(find ", 0) == 0 || name.rfind("package://", 0) == 0 || name.rfind("file://", 0) == 0)
    return reader.file(name, "world");
  const fs::path beside = reader.folder() / name;
  if (!fs::path(name).is_absolute() && fs::is_regular_file(beside, ec))
    return beside.lexically_normal().string();
  std::string error;
  const auto found = findWorldFile(name, reader.resolver(), &error);
  if (!found) reader.error("world", error);
  return found.value_or("");
}

}  // namespace

bool Region::contains(double px, double py) const { return distance(px, py) == 0; }

double Region::distance(double px, double py) const {
  if (radius > 0) return std::max(0.0, std::hypot(px - x, py - y) - radius);
  const double dx = std::max({x_min - px, 0.0, px - x_max});
  const double dy = std::max({y_min - py, 0.0, py - y_max});
  return std::hypot(dx, dy);
}

std::string checkTypeName(Check::Type type) {
  static const char* kNames[] = {"reach",   "clearance",  "no_collision",
                                 "upright", "final_pose", "no_load_warnings"};
  return kNames[static_cast<int>(type)];
}

std::vector<std::string> ScenarioSpec::robotNames(const std::string& model_name) const {
  const std::string base = robot_name.empty() ? model_name : robot_name;
  if (count == 1) return {base};
  std::vector<std::string> names;
  for (int i = 1; i <= count; ++i) names.push_back(base + "_" + std::to_string(i));
  return names;
}

ScenarioSpec parseScenario(const std::string& yaml, const std::string& source,
                           const PackageResolver& resolver) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& error) {
    throw ScenarioError("scenario " + source + ": not YAML: " + error.what());
  }
  Reader reader(source, resolver);
  ScenarioSpec spec;
  spec.source = source;
  spec.name = fs::path(source).stem().string();
  if (!reader.keys(root, "(top level)",
                   {"name", "robot", "world", "spawn", "seed", "duration", "step", "record_period", "drive",
                    "checks", "video"})) {
    reader.throwIfErrors();
  }
  spec.name = reader.string(root, "name", "", spec.name);
  readRobot(reader, root["robot"], spec);
  spec.world = readWorld(reader, root);
  readSpawn(reader, root["spawn"], spec);
  spec.seed = static_cast<uint64_t>(reader.number(root, "seed", "", 0, 0, 9007199254740992.0));
  spec.duration = reader.number(root, "duration", "", spec.duration, 1e-6, kMaxDuration);
  spec.step = reader.number(root, "step", "", spec.step, 1e-6, 0.1);
  spec.record_period = reader.number(root, "record_period", "", spec.record_period, spec.step, kMaxDuration);
  readDrive(reader, root["drive"], spec);
  if (const YAML::Node checks = root["checks"]) {
    if (!checks.IsSequence()) reader.error("checks", "expected a list of checks");
    else
      for (size_t i = 0; i < checks.size(); ++i)
        spec.checks.push_back(readCheck(reader, checks[i], "checks." + std::to_string(i)));
  }
  readVideo(reader, root["video"], spec);
  reader.throwIfErrors();
  return spec;
}

namespace {

std::string readText(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw ScenarioError(what + " [" + path + "] is not a file");
  std::ifstream in(path);
  if (!in) throw ScenarioError("cannot read " + what + " [" + path + "]");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

ScenarioSpec loadScenario(const std::string& path, const PackageResolver& resolver) {
  return parseScenario(readText(path, "scenario"), path, resolver);
}

}  // namespace bullet_sim
