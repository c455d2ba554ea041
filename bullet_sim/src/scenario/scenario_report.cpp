// result.json, trajectory.csv and top.png of a scenario run.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bullet_sim/render/image.h"
#include "bullet_sim/scene/camera.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "bullet_sim/scenario/scenario_run.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

using Json = nlohmann::ordered_json;

constexpr int kTopWidth = 800, kTopHeight = 600;  ///< [px] of top.png

Json figure(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }
Json figure(const std::optional<double>& value) { return value ? figure(*value) : Json(nullptr); }

/// The versions of bullet_sim and the libraries that decide a run's figures (set by CMake).
Json versions() {
  return {{"bullet_sim", BULLET_SIM_VERSION},
          {"bullet", BULLET_SIM_BULLET_VERSION},
          {"embree", BULLET_SIM_EMBREE_VERSION},
          {"sdformat", BULLET_SIM_SDFORMAT_VERSION},
          {"yaml-cpp", BULLET_SIM_YAML_CPP_VERSION},
          {"compiler", __VERSION__}};
}

/// What every result.json starts with: which scenario, from where, and how.
Json header(const RunContext& context) {
  const ScenarioSpec& spec = *context.spec;
  Json json;
  json["scenario"] = spec.name;
  json["file"] = spec.source;
  if (context.matrix) {
    Json values = Json::object();
    for (const auto& [axis, value] : context.matrix_values) values[axis] = value;
    json["matrix"] = {{"file", context.matrix->first}, {"index", context.matrix->second}, {"values", values}};
  }
  json["mode"] = context.mode;
  // The user's nodes run on their own clocks and threads: a launch scenario cannot be repeated exactly.
  json["deterministic"] = context.mode == "timeline";
  json["seed"] = spec.seed;
  json["robot"] = {{"description", spec.description}, {"args", spec.xacro_args}, {"count", spec.count}};
  json["world"] = spec.world;
  json["duration_s"] = spec.duration;
  json["step_s"] = spec.step;
  return json;
}

Json checkJson(const CheckResult& result) {
  return {{"type", result.type},   {"robot", result.robot}, {"passed", result.passed},
          {"value", figure(result.value)}, {"unit", result.unit}, {"limit", figure(result.limit)},
          {"comparison", result.comparison}, {"detail", result.detail}};
}

Json metricsJson(const ScenarioMonitor& monitor) {
  Json metrics = Json::object();
  for (const auto& [name, record] : monitor.records()) {
    Json robot;
    robot["final_x_m"] = record.last.x;
    robot["final_y_m"] = record.last.y;
    robot["final_yaw_rad"] = record.last.yaw;
    robot["distance_m"] = record.distance;
    robot["max_tilt_rad"] = record.max_tilt;
    robot["collision_s"] = record.collision_time;
    robot["min_clearance_m"] = monitor.clearanceCap() > 0
                                   ? figure(std::min(record.min_clearance, monitor.clearanceCap()))
                                   : Json(nullptr);
    robot["min_lidar_range_m"] = figure(record.min_lidar_range);
    metrics[name] = robot;
  }
  return metrics;
}

/// "pass: N checks passed", or what the first failed check measured.
std::string verdictMessage(const std::vector<CheckResult>& results) {
  for (const CheckResult& result : results) {
    if (!result.passed) return "fail: " + result.type + " [" + result.robot + "]: " + result.detail;
  }
  return "pass: " + std::to_string(results.size()) + " check" + (results.size() == 1 ? "" : "s") + " passed";
}

void writeJson(const fs::path& path, const Json& json) {
  std::ofstream out(path);
  out << json.dump(2) << "\n";
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void writeTrajectory(const fs::path& path, const std::vector<TrajectoryRow>& rows) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw std::runtime_error("cannot write " + path.string());
  std::fprintf(file, "time,robot,x,y,z,roll,pitch,yaw,v,w\n");
  for (const TrajectoryRow& row : rows) {
    std::fprintf(file, "%.4f,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", row.time, row.robot.c_str(),
                 row.x, row.y, row.z, row.roll, row.pitch, row.yaw, row.v, row.w);
  }
  std::fclose(file);
}

}  // namespace

Verdict writeOutputs(const std::string& out, const RunContext& context, const ScenarioMonitor& monitor,
                     const Simulation& simulation, SceneRenderer& renderer, RunTiming timing) {
  const auto outputs_start = std::chrono::steady_clock::now();
  fs::create_directories(out);
  writeTrajectory(fs::path(out) / "trajectory.csv", monitor.trajectory());
  const Scene top = simulationScene(simulation, View::kTop, "", monitor.trails().trails());
  std::string error;
  if (!writePng((fs::path(out) / "top.png").string(), renderer.render(top, kTopWidth, kTopHeight), &error))
    throw std::runtime_error(error);

  const std::vector<CheckResult> results = monitor.results();
  bool passed = true;
  Json checks = Json::array();
  for (const CheckResult& result : results) {
    passed = passed && result.passed;
    checks.push_back(checkJson(result));
  }
  const Verdict verdict = passed ? Verdict::kPass : Verdict::kFail;
  Json json = header(context);
  json["verdict"] = verdictName(verdict);
  json["exit_code"] = static_cast<int>(verdict);
  json["message"] = verdictMessage(results);
  json["sim_time_s"] = timing.sim_time;
  json["robots"] = simulation.robotNames();
  json["checks"] = checks;
  json["metrics"] = metricsJson(monitor);
  json["load_warnings"] = monitor.loadWarnings();
  json["outputs"] = {{"trajectory", "trajectory.csv"}, {"top_view", "top.png"}};
  if (fs::exists(fs::path(out) / "video.mp4")) json["outputs"]["video"] = "video.mp4";
  if (!context.launch_log.empty()) json["outputs"]["launch_log"] = context.launch_log;
  const auto now = std::chrono::steady_clock::now();
  // Everything under "timing" varies from run to run; every other figure is the same for the same inputs.
  json["timing"] = {{"wall_s", std::chrono::duration<double>(now - timing.start).count()},
                    {"setup_s", timing.setup},
                    {"stepping_s", timing.stepping},
                    {"outputs_s", std::chrono::duration<double>(now - outputs_start).count()},
                    {"rtf", figure(timing.sim_time / timing.stepping)}};
  json["versions"] = versions();
  writeJson(fs::path(out) / "result.json", json);
  return verdict;
}

void writeErrorResult(const std::string& out, const RunContext& context, const std::string& why) {
  Json json = context.spec ? header(context) : Json::object();
  json["verdict"] = verdictName(Verdict::kError);
  json["exit_code"] = static_cast<int>(Verdict::kError);
  json["message"] = "could not run: " + why;
  json["versions"] = versions();
  std::error_code ec;
  fs::create_directories(out, ec);
  writeJson(fs::path(out) / "result.json", json);
}

}  // namespace bullet_sim
