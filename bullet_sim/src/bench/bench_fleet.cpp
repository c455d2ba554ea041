#include "bench/bench_fleet.h"

#include <algorithm>
#include <cmath>

#include "bullet_sim/tools/process_stats.h"
#include "tools/command_line.h"

namespace bullet_sim {
namespace {

using Json = nlohmann::ordered_json;

constexpr double kPushedDistance = 0.01;  ///< [m] a loose body moved this far was pushed

/// A figure: null when it is not finite.
Json figure(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

/// The scans a robot's lidars (2D and 3D) have published so far.
uint64_t lidarScans(const Robot& robot) {
  uint64_t scans = 0;
  for (const auto& output : robot.outputs<LaserScan>()) scans += output.stream->count();
  for (const auto& output : robot.outputs<PointCloud>()) scans += output.stream->count();
  return scans;
}

/// Every robot's drive axle.
std::vector<Planar> axlePoses(const std::vector<Robot*>& robots, const std::vector<Drive>& drives) {
  std::vector<Planar> poses;
  for (size_t k = 0; k < robots.size(); ++k) poses.push_back(axlePose(*robots[k], drives[k].joints));
  return poses;
}

/// Parses and spawns `count` robots on the grid, timed into `run`.
std::vector<Robot*> spawnFleet(Simulation& simulation, int count, const FleetOptions& options,
                               std::vector<std::string>* warnings, FleetRun& run) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  std::vector<Robot*> robots;
  const Clock::time_point start = Clock::now();
  for (int k = 0; k < count; ++k) {
    const std::string name = "robot" + std::to_string(k + 1);
    SpawnPose pose = gridPose(k, count, options.spacing, options.origin);
    pose.robot_namespace = name;
    ModelSpec model = parseModel(options.urdf, options.source, resolver, warnings, options.limits);
    robots.push_back(&simulation.spawn(name, std::move(model), pose, warnings));
  }
  run.spawn_s = secondsSince(start);
  return robots;
}

/// The distance between two poses' positions [m].
double distance(const Planar& a, const Planar& b) { return std::hypot(a.x - b.x, a.y - b.y); }

/// What the runs did to the world's loose bodies and to the robots, the worst of every run: whether anything
/// flew, sank or went through a wall.
void addWatchFigures(const std::vector<FleetRun>& runs, Json& json) {
  double rise = 0, sink = 0, robot_rise = 0, robot_sink = 0, tilt = 0, clearance = INFINITY;
  size_t pushed = 0, asleep = runs.empty() ? 0 : SIZE_MAX;
  std::vector<std::string> escaped;
  for (const FleetRun& run : runs) {
    size_t pushed_in_run = 0;
    for (const LooseBodyTrack& body : run.loose) {
      rise = std::max(rise, body.z_max - body.start.z());
      sink = std::max(sink, body.start.z() - body.z_min);
      if (body.moved_max > kPushedDistance) ++pushed_in_run;
      const bool listed = std::find(escaped.begin(), escaped.end(), body.name) != escaped.end();
      if (body.escaped && !listed) escaped.push_back(body.name);
    }
    pushed = std::max(pushed, pushed_in_run);
    const auto sleeper = [](const LooseBodyTrack& body) { return body.asleep; };
    asleep =
        std::min(asleep, static_cast<size_t>(std::count_if(run.loose.begin(), run.loose.end(), sleeper)));
    for (const RobotTrack& robot : run.robots) {
      robot_rise = std::max(robot_rise, robot.rise_max);
      robot_sink = std::max(robot_sink, robot.sink_max);
      tilt = std::max(tilt, robot.tiltMax());
    }
    clearance = std::min(clearance, run.start_clearance);
  }
  json["loose_bodies"] = runs.empty() ? 0 : runs.front().loose.size();
  json["spawn_clearance_m"] = figure(clearance);
  json["loose_pushed"] = pushed;
  json["loose_rise_max_m"] = rise;
  json["loose_sink_max_m"] = sink;
  json["loose_escaped"] = escaped;
  json["loose_asleep_at_end"] = asleep;
  json["robot_rise_max_m"] = robot_rise;
  json["robot_sink_max_m"] = robot_sink;
  json["robot_tilt_max_deg"] = tilt * 180 / M_PI;
}

/// The figures of one fleet's runs: medians first, then every run's.
Json countFigures(int count, const std::vector<FleetRun>& runs, const FleetOptions& options) {
  std::vector<double> rtf, wall_ms, cpu_ms, process_cpu_ms, spawn_s, rss_mb, shared;
  double pose_error = 0, scan_rate = NAN;
  for (const FleetRun& run : runs) {
    rtf.push_back(options.duration / run.drive_s);
    wall_ms.push_back(1e3 * run.drive_s / (options.duration * count));
    cpu_ms.push_back(1e3 * run.cpu_s / (options.duration * count));
    process_cpu_ms.push_back(1e3 * run.process_cpu_s / (options.duration * count));
    spawn_s.push_back(run.spawn_s);
    shared.push_back(100 * run.shared_solves);
    rss_mb.push_back(run.rss_mb);
    for (size_t k = 0; k < run.end.size(); ++k) {
      const Planar ideal = unicycle(run.settled[k], options.v, options.w, options.duration);
      pose_error = std::max(pose_error, distance(run.end[k], ideal));
    }
    scan_rate = static_cast<double>(run.lidar_scans) / (options.duration * count);
  }
  Json json;
  json["robots"] = count;
  json["rtf"] = figure(median(rtf));
  json["wall_ms_per_sim_s_per_robot"] = figure(median(wall_ms));
  json["cpu_ms_per_sim_s_per_robot"] = figure(median(cpu_ms));
  json["process_cpu_ms_per_sim_s_per_robot"] = figure(median(process_cpu_ms));
  json["shared_solves_pct"] = figure(median(shared));
  json["robot_rtf"] = figure(count * median(rtf));
  json["spawn_s"] = figure(median(spawn_s));
  json["peak_rss_mb"] = peakRssMb();
  json["rss_mb"] = figure(median(rss_mb));
  json["lidar_scans_per_robot_per_s"] = figure(scan_rate);
  json["pose_error_max_m"] = pose_error;
  addWatchFigures(runs, json);
  json["rtf_runs"] = rtf;
  json["spawn_s_runs"] = spawn_s;
  json["cpu_ms_per_sim_s_per_robot_runs"] = cpu_ms;
  json["process_cpu_ms_per_sim_s_per_robot_runs"] = process_cpu_ms;
  return json;
}

}  // namespace

SpawnPose gridPose(int index, int count, double spacing, const SpawnPose& origin) {
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count))));
  const int rows = (count + columns - 1) / columns;
  SpawnPose pose = origin;
  pose.x = origin.x + (index % columns - (columns - 1) / 2.0) * spacing;
  pose.y = origin.y + (index / columns - (rows - 1) / 2.0) * spacing;
  return pose;
}

FleetRun driveFleet(const WorldSpec& world, int count, const FleetOptions& options,
                    std::vector<std::string>* warnings) {
  FleetRun run;
  SimulationOptions simulation_options;
  simulation_options.physics.step_size = options.step;
  simulation_options.limits = options.limits;
  simulation_options.threads = options.threads;
  simulation_options.lockstep = options.lockstep;
  Simulation simulation(world, simulation_options);
  const std::vector<Robot*> robots = spawnFleet(simulation, count, options, warnings, run);
  std::vector<Drive> drives;
  for (const Robot* robot : robots) drives.push_back(driveOf(*robot, options.source));
  FleetWatch watch(simulation, {robots.begin(), robots.end()});

  for (long i = 0; i < std::lround(kSettleTime / options.step); ++i) {
    simulation.step();
    watch.sample();
  }
  run.settled = axlePoses(robots, drives);
  simulation.finishCasts();  // the settling's scans are not the drive's
  if (options.snapshot) options.snapshot(simulation, count, "settled");
  uint64_t scans_before = 0;
  for (const Robot* robot : robots) scans_before += lidarScans(*robot);

  const long steps = std::lround(options.duration / options.step);
  const long resend = std::max(1L, std::lround(kCommandPeriod / options.step));
  const Twist command{{options.v, 0, 0}, {0, 0, options.w}};
  const Clock::time_point start = Clock::now();
  const double cpu_start = threadCpuSeconds();
  const double process_cpu_start = processCpuSeconds();
  const uint64_t shared_before = simulation.sharedSolves();
  for (long i = 0; i < steps; ++i) {
    if (i % resend == 0) {
      for (const Drive& drive : drives) (*drive.command)(command, simulation.time());
    }
    simulation.step();
    watch.sample();
  }
  simulation.finishCasts();
  run.drive_s = secondsSince(start);
  run.cpu_s = threadCpuSeconds() - cpu_start;
  run.process_cpu_s = processCpuSeconds() - process_cpu_start;
  run.shared_solves = static_cast<double>(simulation.sharedSolves() - shared_before) /
                      static_cast<double>(steps * simulation.physicsSubsteps());
  run.rss_mb = currentRssMb();
  run.end = axlePoses(robots, drives);
  for (const Robot* robot : robots) run.lidar_scans += lidarScans(*robot);
  run.lidar_scans -= scans_before;
  run.loose = watch.loose();
  run.robots = watch.robots();
  run.start_clearance = watch.startClearance();
  if (options.snapshot) options.snapshot(simulation, count, "end");
  return run;
}

Json fleetFigures(const WorldSpec& world, std::vector<int> counts, int repeat, const FleetOptions& options,
                  std::vector<std::string>* warnings) {
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  Json fleets = Json::array();
  for (int count : counts) {
    std::vector<FleetRun> runs;
    FleetOptions later = options;  // the first run's pictures are enough
    later.snapshot = nullptr;
    for (int i = 0; i < repeat; ++i)
      runs.push_back(driveFleet(world, count, i == 0 ? options : later, warnings));
    fleets.push_back(countFigures(count, runs, options));
  }
  return fleets;
}

}  // namespace bullet_sim
