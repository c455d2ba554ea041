#include "bench/bench_strikes.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "bullet_sim/assets/package_resolver.h"
#include "bullet_sim/model/world.h"
#include "bullet_sim/render/image.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "bullet_sim/tools/strike_matrix.h"
#include "tools/command_line.h"

namespace bullet_sim {

namespace {

using Json = nlohmann::ordered_json;

/// The shipped robots and the look-alikes, expanded.
std::vector<StrikeRobot> strikeRobots() {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  const auto file = [&](const std::string& package, const std::string& relative) {
    const auto dir = resolver.packageDirectory(package);
    if (!dir) throw Failure("package [" + package + "] is not on ROS_PACKAGE_PATH");
    return *dir + "/" + relative;
  };
  std::vector<StrikeRobot> robots;
  const std::vector<std::pair<std::string, std::string>> shipped = {
      {"smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro"},
      {"smartcar_description", "urdf/smartcar.urdf.xacro"},
      {"yahboomcar_description", "urdf/yahboomcar.urdf.xacro"},
      {"tianracer_description", "urdf/tianracer.urdf.xacro"}};
  for (const auto& [package, xacro] : shipped)
    robots.push_back({package, runXacro(file(package, xacro), {}), ""});
  robots.push_back({"rover_description", runXacro(file("rover_description", "urdf/rover.urdf.xacro"), {}),
                    readUrdfFile(file("rover_description", "config/control.yaml"))});
  for (const std::string name : {"caster_two_wheeler", "light_skid_steer", "tall_base"})
    robots.push_back({name, readUrdfFile(file("bullet_sim", "test/fixtures/contact/" + name + ".urdf")), ""});
  return robots;
}

/// Every cell of issue 28's matrix: each wheel model, each step size (1 and 10 ms unless told), 0.1 to 2 m/s,
/// head-on, 30 and 60 degrees, into the wall and the door's edge; the 2 cm panel head-on; and coasting in,
/// motors off, for the energy.
std::vector<StrikeCell> strikeCells(const std::vector<double>& steps) {
  std::vector<StrikeCell> cells;
  for (const std::string model : {"raycast", "contact"}) {
    for (double step : steps) {
      for (StrikeTarget target : {StrikeTarget::kWall, StrikeTarget::kDoorEdge}) {
        for (double degrees : {0.0, 30.0, 60.0}) {
          for (double speed : {0.1, 0.5, 1.0, 2.0})
            cells.push_back({model, step, speed, degrees * M_PI / 180, target});
        }
      }
      cells.push_back({model, step, 2.0, 0, StrikeTarget::kPanel});
      for (double speed : {0.5, 2.0}) {
        for (StrikeTarget target : {StrikeTarget::kWall, StrikeTarget::kDoorEdge})
          cells.push_back({model, step, speed, 0, target, /*coast=*/true});
      }
    }
  }
  return cells;
}

bool matches(const std::string& name, const std::vector<std::string>& filter) {
  for (const auto& word : filter) {
    if (name.find(word) == std::string::npos) return false;
  }
  return true;
}

Json cellJson(const std::string& name, const StrikeCell& cell, const StrikeOutcome& outcome) {
  const StrikeBounds& b = outcome.bounds;
  Json json;
  json["cell"] = name;
  json["passed"] = outcome.passed();
  json["failures"] = outcome.failures;
  json["max_tilt_rad"] = outcome.max_tilt;
  json["rise_m"] = outcome.rise;
  json["root_rise_m"] = outcome.root_rise;
  json["penetration_m"] = outcome.penetration;
  json["path_m"] = outcome.path;
  json["command_path_m"] = outcome.command_path;
  json["given_speed"] = outcome.given_speed;
  if (cell.coast) json["energy_gain_j"] = outcome.energy_gain;
  json["bounds"] = {{"mass_kg", b.mass},
                    {"com_height_m", b.com_height},
                    {"contact_height_m", b.contact_height},
                    {"front_m", b.front},
                    {"rear_m", b.rear},
                    {"impact_energy_j", b.impact_energy},
                    {"barrier_j", b.barrier},
                    {"tip_speed_mps", std::isfinite(b.tip_speed) ? Json(b.tip_speed) : Json()},
                    {"push_n", b.push},
                    {"wheel_first", b.wheel_first},
                    {"impact_tips", b.impact_tips},
                    {"stall_tips", b.stall_tips},
                    {"climb_ratio", b.climb_ratio}};
  return json;
}

/// A cell's name as a file name's stem.
std::string fileStem(const std::string& cell) {
  std::string stem = cell;
  for (char& c : stem) {
    if (c == ' ' || c == '/') c = '_';
  }
  return stem;
}

/// Writes `dir`/<cell>_trail.csv: the root link every 50 ms of the run.
void writeTrail(const std::string& dir, const std::string& cell, const std::vector<StrikeTrailPoint>& trail) {
  std::ofstream csv(dir + "/" + fileStem(cell) + "_trail.csv");
  csv << "time,x,y,z,roll,pitch,yaw,vx,vy,vz,wx,wy,wz,tilt\n";
  for (const auto& p : trail) {
    csv << p.time;
    for (const Eigen::Vector3d* v : {&p.position, &p.rpy, &p.linear, &p.angular}) {
      for (int i = 0; i < 3; ++i) csv << "," << (*v)[i];
    }
    csv << "," << p.tilt << "\n";
  }
  if (!csv) std::cerr << "bench: cannot write the trail of [" << cell << "] into " << dir << "\n";
}

/// Writes `dir`/<cell>_<moment>_side.png and _chase.png.
StrikeSnapshot strikePictures(const std::string& dir, const std::string& cell) {
  const std::string stem = fileStem(cell);
  return [dir, stem](const Simulation& simulation, const std::string& robot, const std::string& moment) {
    static OffscreenRenderer renderer;
    Scene scene = simulationScene(simulation, View::kChase, robot);
    const Eigen::Vector3d target = scene.camera.target, eye = scene.camera.eye;
    const Eigen::Vector3d heading = (target - eye).cwiseProduct(Eigen::Vector3d(1, 1, 0)).normalized();
    std::string error;
    writePng(dir + "/" + stem + "_" + moment + "_chase.png", renderer.render(scene, 640, 480), &error);
    const double distance = (target - eye).norm();
    scene.camera.eye = target + distance * Eigen::Vector3d::UnitZ().cross(heading) +
                       0.1 * distance * Eigen::Vector3d::UnitZ();
    if (!writePng(dir + "/" + stem + "_" + moment + "_side.png", renderer.render(scene, 640, 480), &error))
      std::cerr << "bench: " << error << "\n";
  };
}

}  // namespace

Json strikeMatrixReport(const StrikeMatrixOptions& options) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  const auto worlds = resolver.packageDirectory("bullet_sim");
  if (!worlds) throw Failure("package [bullet_sim] is not on ROS_PACKAGE_PATH");
  const WorldSpec world = loadWorld(*worlds + "/worlds/empty.world", resolver, nullptr);
  if (!options.render_dir.empty()) {
    std::error_code error;  // made up front, as --snapshot's: a matrix must not run on without its pictures
    std::filesystem::create_directories(options.render_dir, error);
    if (error) throw Failure("--strike-render: cannot make [" + options.render_dir + "]: " + error.message());
  }
  int cells = 0, passed = 0;
  double tilt = 0, rise = 0, energy = 0;
  std::map<double, std::pair<double, double>> timing;  // per step: sim s, wall s
  Json failed = Json::array(), all = Json::array();
  for (const StrikeRobot& robot : strikeRobots()) {
    for (const StrikeCell& cell : strikeCells(options.steps)) {
      const std::string name = cellName(robot, cell);
      if (!matches(name, options.filter)) continue;
      const StrikeOutcome outcome =
          runStrike(robot, cell, world,
                    options.render_dir.empty() ? StrikeSnapshot() : strikePictures(options.render_dir, name));
      if (!options.render_dir.empty()) writeTrail(options.render_dir, name, outcome.trail);
      ++cells;
      passed += outcome.passed();
      tilt = std::max(tilt, outcome.max_tilt);
      rise = std::max(rise, outcome.rise);
      if (cell.coast) energy = std::max(energy, outcome.energy_gain);
      timing[cell.step].first += outcome.sim_seconds;
      timing[cell.step].second += outcome.wall_seconds;
      const Json json = cellJson(name, cell, outcome);
      if (!outcome.passed()) failed.push_back(json);
      if (options.list_cells) all.push_back(json);
      std::cerr << (outcome.passed() ? "pass " : "FAIL ") << name << "\n";
    }
  }
  Json report;
  report["cells"] = cells;
  report["passed"] = passed;
  report["max_tilt_rad"] = tilt;
  report["max_rise_m"] = rise;
  report["max_energy_gain_j"] = energy;
  for (const auto& [step, times] : timing) {
    std::ostringstream key;  // as the cells' names write the step: rtf_1ms, rtf_0.5ms
    key << "rtf_" << step * 1000 << "ms";
    report[key.str()] = times.first / times.second;
  }
  report["failed"] = failed;
  if (options.list_cells) report["all"] = all;
  return report;
}

}  // namespace bullet_sim
