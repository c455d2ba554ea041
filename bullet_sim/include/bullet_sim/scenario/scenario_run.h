// Running a scenario: its world and robots loaded, spawned, driven by its timeline, and its outputs written
// (result.json, trajectory.csv, top.png, and video.mp4 when asked). ROS-free: a launch scenario's simulator
// node uses the same pieces around its own loop.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/model/model.h"
#include "bullet_sim/model/world.h"
#include "bullet_sim/scene/scene_renderer.h"
#include "bullet_sim/simulation/simulation.h"
#include "bullet_sim/scenario/scenario_monitor.h"
#include "bullet_sim/scenario/scenario_file.h"
#include "bullet_sim/tools/run_recorder.h"

namespace bullet_sim {

/// The exit codes of `scenario`, and what result.json's verdict says.
enum class Verdict { kPass = 0, kFail = 1, kError = 2 };
std::string verdictName(Verdict verdict);

/// A scenario's world and robot model, loaded and checked.
struct ScenarioAssets {
  std::string urdf;  ///< the robot's, expanded, with the scenario's wheel model
  WorldSpec world;
  ModelSpec model;
  std::vector<std::string> robot_names;
  std::vector<std::string> warnings;  ///< of the world and the robot's description
};

/// Loads the world and the robot (an xacro through the cache of xacro_cache.h), with the scenario's wheel
/// model. Throws SpecError or std::runtime_error saying what is wrong.
ScenarioAssets loadAssets(const ScenarioSpec& spec, const PackageResolver& resolver);

/// Spawns the scenario's robots at its poses. Throws SpecError when one cannot be spawned.
void spawnRobots(Simulation& simulation, const ScenarioSpec& spec, const ScenarioAssets& assets,
                 std::vector<std::string>* warnings);

/// Sends a timeline's cmd_vel to the robots' drive plugins (every Twist input of each robot).
class TimelineDriver {
 public:
  /// Throws ScenarioError when a robot has no cmd_vel input, or a segment names no robot of the run.
  TimelineDriver(const ScenarioSpec& spec, const Simulation& simulation);
  /// Sends what is due at the step about to be taken, and tells `recorder` (when given) what it sent.
  void beforeStep(const Simulation& simulation, RunRecorder* recorder = nullptr);

 private:
  std::vector<TimelineSegment> segments_;
  std::vector<double> starts_;  ///< [s] per segment
  std::vector<std::string> robots_;
  long steps_per_resend_ = 100;
};

class VideoWriter;

/// A run's video.mp4: the chase view of the first robot with the trails, a frame at every multiple of
/// 1 / video.fps of sim time showing the simulation then.
class ScenarioVideo {
 public:
  /// Throws std::runtime_error when the file cannot be written.
  ScenarioVideo(const std::string& path, const ScenarioSpec& spec, SceneRenderer& renderer);
  ~ScenarioVideo();
  void afterStep(const Simulation& simulation, const ScenarioMonitor& monitor);
  void finish();

 private:
  std::unique_ptr<VideoWriter> writer_;
  int width_, height_;
  SceneRenderer& renderer_;
  double period_;  ///< [s]
  double next_;    ///< [s]
};

/// Where a run's time went [s of wall time].
struct RunTiming {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  double setup = 0;    ///< loading and spawning
  double stepping = 0;  ///< the simulated duration
  double sim_time = 0;  ///< [s] of sim time stepped
};

/// What result.json says besides the checks.
struct RunContext {
  const ScenarioSpec* spec = nullptr;
  std::string mode = "timeline";  ///< or "launch"
  std::optional<std::pair<std::string, int>> matrix;  ///< the matrix file and the cell's index
  std::vector<std::pair<std::string, std::string>> matrix_values;
  std::string launch_log;  ///< a launch scenario's log file
};

/// Writes result.json, trajectory.csv and top.png into `out` (made when missing) and returns the verdict:
/// pass when every check passed. `simulation` is drawn as it is now, with the monitor's trails.
Verdict writeOutputs(const std::string& out, const RunContext& context, const ScenarioMonitor& monitor,
                     const Simulation& simulation, SceneRenderer& renderer, RunTiming timing);

/// Writes result.json for a run that could not happen, with `why`.
void writeErrorResult(const std::string& out, const RunContext& context, const std::string& why);

/// Records a run's robots into a bag (bagSettings), each in its own namespace and tf_prefix, of its name,
/// when there are several (as a launch scenario has them). Errors writing it go to stderr; the run goes on.
std::unique_ptr<RunRecorder> recordRobots(const BagSettings& settings, const Simulation& simulation);

/// Runs a timeline scenario in-process into `out`; `video` adds video.mp4 of the chase view, `bag` a rosbag.
/// Throws ScenarioError, SpecError or std::runtime_error when it cannot run.
Verdict runTimeline(const ScenarioSpec& spec, const RunContext& context, const std::string& out, bool video,
                    const std::optional<BagSettings>& bag = std::nullopt);

}  // namespace bullet_sim
