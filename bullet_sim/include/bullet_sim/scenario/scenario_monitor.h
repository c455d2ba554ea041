// What a scenario run shows: each robot's path, and what each of the scenario's checks measures, watched
// after every step of the simulation, whoever steps it (the timeline runner, or the simulator node under a
// launch).
#pragma once

#include <Eigen/Geometry>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/physics/clearance.h"
#include "bullet_sim/scene/recording.h"
#include "bullet_sim/simulation/simulation.h"
#include "bullet_sim/scenario/scenario_file.h"

namespace bullet_sim {

/// One robot at one time: the root link's pose and its speeds in its own heading.
struct TrajectoryRow {
  double time = 0;  ///< [s]
  std::string robot;
  double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;  ///< [m], [rad]
  double v = 0;  ///< [m/s] along the heading
  double w = 0;  ///< [rad/s] about the vertical
};

/// A check's verdict for one robot: the measured value against its limit.
struct CheckResult {
  std::string type;   ///< "reach", "clearance", ...
  std::string robot;
  bool passed = false;
  std::optional<double> value;  ///< nullopt when nothing was measured (a region never reached)
  std::string unit;
  double limit = 0;
  std::string comparison;  ///< "<=" or ">=": how value must compare with limit
  std::string detail;      ///< what a user reads first: where, when, what
};

/// What one robot did over the run, for checks and the result's metrics.
struct RobotRecord {
  double distance = 0;  ///< [m] travelled by the root link in the plane
  double max_tilt = 0;  ///< [rad]
  double min_clearance = 0;  ///< [m], to the world's obstacles, when measured (see clearance_cap)
  std::string clearance_obstacle;
  double clearance_time = 0;
  std::optional<double> min_lidar_range;  ///< [m] over every scan of its lidars
  double lidar_time = 0;
  double collision_time = 0;  ///< [s] in contact with an obstacle (ground support left out)
  std::optional<double> first_collision;
  std::string first_collision_with;
  std::vector<std::optional<double>> reached;  ///< per check: the first time in the region
  std::vector<double> region_distance;           ///< per check: the nearest it came [m]
  TrajectoryRow last;
};

class ScenarioMonitor {
 public:
  /// Watches the robots now in `simulation`, named as `spec` names them. `load_warnings` are the run's
  /// (parsing, world, spawn). Throws ScenarioError when a check cannot be measured (a lidar check on a robot
  /// without a lidar, a check naming no robot of the run).
  ScenarioMonitor(const ScenarioSpec& spec, const Simulation& simulation,
                  std::vector<std::string> load_warnings);
  ~ScenarioMonitor();

  /// Records the step the simulation has just taken.
  void afterStep(const Simulation& simulation);

  /// Every check's verdict, per robot, as of the last step.
  std::vector<CheckResult> results() const;
  const std::vector<TrajectoryRow>& trajectory() const { return trajectory_; }
  const std::map<std::string, RobotRecord>& records() const { return records_; }
  const std::vector<std::string>& loadWarnings() const { return load_warnings_; }
  /// Each robot's path, for pictures.
  const Recording& trails() const { return trails_; }
  /// Geometric clearances above this are reported as this [m].
  double clearanceCap() const { return clearance_cap_; }

 private:
  void recordPose(const Simulation& simulation, const Robot& robot, RobotRecord& record);
  void recordClearance(const Robot& robot, double time, RobotRecord& record);
  /// The nearest range of the robot's scans and point clouds published since the last step.
  void recordLidar(const Robot& robot, RobotRecord& record);
  template <class Sample>
  void recordRanges(const Robot& robot, RobotRecord& record);
  void recordContacts(const Simulation& simulation, const Robot& robot, RobotRecord& record);
  CheckResult evaluate(const Check& check, size_t index, const std::string& robot) const;

  ScenarioSpec spec_;
  std::vector<std::string> robots_;
  std::vector<std::string> load_warnings_;
  std::map<std::string, RobotRecord> records_;
  std::map<std::string, uint64_t> scans_seen_;
  std::vector<TrajectoryRow> trajectory_;
  Recording trails_{0};
  std::unique_ptr<ClearanceQuery> clearance_;  ///< only when a check wants it
  double clearance_cap_ = 0;
  double next_row_ = 0;
  double next_clearance_ = 0;
};

}  // namespace bullet_sim
