// A scenario file: one run of the simulator, described in YAML (parsed with yaml-cpp), and a matrix file that
// crosses scenario fields into many runs. ROS-free. docs/scenarios.md is the user's guide.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bullet_sim/assets/package_resolver.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

/// A scenario that cannot be read: what() names the file and the key, and says what is expected.
class ScenarioError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One segment of a timeline: the cmd_vel sent for `duration`, re-sent every 0.1 s as `rostopic pub -r 10`
/// does. After the last segment the robots are commanded to stop.
struct TimelineSegment {
  double duration = 0;  ///< [s] of sim time
  double v = 0;         ///< linear.x [m/s]
  double vy = 0;        ///< linear.y [m/s] (holonomic drives)
  double w = 0;         ///< angular.z [rad/s], REP 103: + is counter-clockwise
  std::string robot;    ///< "" = every robot
};

/// The user's own nodes: a launch file, started with its args beside a simulator on a master of its own.
struct LaunchDrive {
  std::string file;                                        ///< resolved path
  std::vector<std::pair<std::string, std::string>> args;  ///< name, value
  /// Topics that need a publisher before the clock starts; empty = every robot's command topic.
  std::vector<std::string> wait_for;
  double ready_timeout = 30;   ///< [s] of wall time for the launch to come up
  double real_time_factor = 0;  ///< 0 = as fast as possible
};

/// A region of the plane: a circle (radius > 0) or an axis-aligned box (x and y ranges).
struct Region {
  double x = 0, y = 0, radius = 0;              ///< [m]
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;  ///< [m], when radius is 0
  bool contains(double px, double py) const;
  double distance(double px, double py) const;  ///< [m], 0 inside
};

/// What a run must show. Each check applies to every robot, or to the one it names.
struct Check {
  enum class Type { kReach, kClearance, kNoCollision, kUpright, kFinalPose, kNoLoadWarnings };
  Type type = Type::kReach;
  std::string robot;  ///< "" = every robot
  // kReach: the root link enters `region` no later than `by` [s].
  Region region;
  double by = 0;
  // kClearance: never closer than `min` [m] to an obstacle, from the lidar's ranges or from the collision
  // geometry (the distance between the robot's collision shapes and the world's, the ground left out).
  double min = 0;
  bool from_lidar = false;
  // kUpright: the root link's z axis never tilts more than `max_tilt` [rad] from the vertical.
  double max_tilt = 0;
  // kFinalPose: where the root link ends: x, y [m], yaw [rad], within the tolerances [m], [rad].
  double x = 0, y = 0, yaw = 0, position_tolerance = 0, yaw_tolerance = 0;
  bool check_yaw = false;
};

/// Type names as written in the file ("reach", "clearance", ...).
std::string checkTypeName(Check::Type type);

struct ScenarioSpec {
  std::string name;    ///< the file's `name`, or its file name without extension
  std::string source;  ///< the file, for messages
  // The robot.
  std::string description;                ///< resolved URDF or xacro path
  std::vector<std::string> xacro_args;    ///< "name:=value"
  std::string robot_name;                 ///< "" = the model's name
  int count = 1;
  std::vector<SpawnPose> spawn;           ///< one per robot
  std::optional<std::string> wheel_model;  ///< sets <wheelModel> in the drive plugins
  // The world and the run.
  std::string world;  ///< resolved .world path
  uint64_t seed = 0;
  double duration = 10;  ///< [s] of sim time
  double step = 0.001;   ///< [s]
  double record_period = 0.05;  ///< [s] between trajectory rows
  // What drives the robots: a timeline, or a launch file.
  std::vector<TimelineSegment> timeline;
  std::optional<LaunchDrive> launch;
  std::vector<Check> checks;
  // Pictures.
  double video_fps = 25;
  int video_width = 640, video_height = 480;

  /// The robots' names: robot_name (or the model's) for one, NAME_1 ... NAME_N for several.
  std::vector<std::string> robotNames(const std::string& model_name) const;
};

/// Reads a scenario file. Paths in it are relative to its folder, or package://pkg/..., or $(find pkg)/...;
/// a world may also be a name found in bullet_sim's or bullet_sim_bringup's worlds. Throws ScenarioError
/// naming the file and every bad key at once.
ScenarioSpec loadScenario(const std::string& path, const PackageResolver& resolver);

/// The same for YAML text that came from `source` (its folder resolves relative paths).
ScenarioSpec parseScenario(const std::string& yaml, const std::string& source,
                           const PackageResolver& resolver);

/// A matrix file: a scenario file and axes (dotted keys of the scenario, each with its values) whose cross
/// product is the runs; the last axis varies fastest.
struct MatrixCell {
  int index = 0;
  std::vector<std::pair<std::string, std::string>> values;  ///< axis, its value as YAML (flow style)
  std::string yaml;  ///< the scenario with the values put in
};

struct Matrix {
  std::string name;                              ///< the file's `name`, or its file name
  std::string source;                            ///< the matrix file
  std::string scenario;                          ///< the base scenario file
  std::string scenario_yaml;                     ///< its text
  std::vector<std::string> axes;  ///< dotted keys: "world", "robot.args.with_lidar", "spawn.0.x"
  std::vector<std::vector<std::string>> values;  ///< per axis, each value as YAML
  int count = 0;                                 ///< the product of the axes' sizes

  /// Cell `index` (0 <= index < count); ScenarioError when an axis cannot be put into the scenario.
  MatrixCell cell(int index) const;
  /// Only the axis values of cell `index`, without building its scenario (a million cells list in seconds).
  std::vector<std::pair<std::string, std::string>> valuesOf(int index) const;
};

/// Reads a matrix file; ScenarioError names the file and what is wrong.
Matrix loadMatrix(const std::string& path);

/// A scenario of a matrix's cell, its relative paths resolved against the base scenario's folder.
ScenarioSpec cellScenario(const Matrix& matrix, int index, const PackageResolver& resolver);

}  // namespace bullet_sim
