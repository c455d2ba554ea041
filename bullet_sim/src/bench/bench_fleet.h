// bench --robots: N copies of one robot in one world, every one driving a circle with its lidars scanning
// (issue 32, "Many robots in one world"): RTF, what each robot costs per sim second, the time to spawn them,
// memory.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"
#include "bench/bench_drive.h"
#include "bench/fleet_watch.h"

namespace bullet_sim {

struct FleetOptions {
  std::string urdf;         ///< the robot's URDF, parsed for every spawn as the node's spawn service does
  std::string source;       ///< where it came from, for messages
  double step = 0.001;      ///< [s]
  double duration = 10;     ///< [s] of driving, after kSettleTime at rest
  double v = 0.3, w = 0.3;  ///< [m/s], [rad/s], sent to every robot every kCommandPeriod of sim time
  double spacing = 1.5;     ///< [m] between neighbours on the grid
  SpawnPose origin;         ///< the grid's centre (x, y) and every robot's yaw
  Limits limits;
  int threads = 0;  ///< the simulation's pool (SimulationOptions::threads)
  bool lockstep = false;  ///< scans cast within their step (SimulationOptions::lockstep), not behind physics
  /// When set, driveFleet calls it with the simulation, the fleet's size and the moment ("settled" or "end"),
  /// outside the timed drive; fleetFigures sets it for the first run of each fleet only.
  std::function<void(const Simulation&, int count, const std::string& moment)> snapshot;
};

/// One fleet's spawn, settle and drive.
struct FleetRun {
  double spawn_s = 0;        ///< [wall s] parsing the URDF and spawning, for every robot
  double drive_s = 0;        ///< [wall s] of the drive, the settling left out
  double cpu_s = 0;          ///< [s] the drive's CPU time on the simulation's thread
  double process_cpu_s = 0;  ///< [s] the drive's CPU time on every thread (the pool's too)
  double rss_mb = 0;         ///< resident memory at the end of the drive [MB]
  uint64_t lidar_scans = 0;  ///< scans every robot's ray sensors published while driving
  double shared_solves = 0;  ///< the share of the drive's substeps whose islands' solve the pool shared
  std::vector<Planar> settled, end;  ///< every robot's drive axle before and after the drive, in spawn order
  /// The world's loose bodies and every robot (in spawn order), from the spawn to the end of the drive.
  std::vector<LooseBodyTrack> loose;
  std::vector<RobotTrack> robots;
  double start_clearance = 0;  ///< [m] FleetWatch::startClearance
};

/// Where robot `index` of `count` stands: a square grid (its columns along x, rows along y) `spacing` apart,
/// centred on the origin's x and y, every robot at the origin's yaw.
SpawnPose gridPose(int index, int count, double spacing, const SpawnPose& origin);

/// Spawns `count` robots robot1 ... robotN, each in the namespace of its name, into a simulation of `world`;
/// lets them settle, then drives every one at v and w for the duration. Load messages go to `warnings`.
FleetRun driveFleet(const WorldSpec& world, int count, const FleetOptions& options,
                    std::vector<std::string>* warnings);

/// `repeat` runs of each of `counts` (in increasing order, so that the process's peak memory is the largest
/// fleet's so far), as a JSON array: per count, the medians and every run's figures.
nlohmann::ordered_json fleetFigures(const WorldSpec& world, std::vector<int> counts, int repeat,
                                    const FleetOptions& options, std::vector<std::string>* warnings);

}  // namespace bullet_sim
