#include "bullet_sim/scenario/scenario_monitor.h"

#include <algorithm>
#include <cmath>
#include <sstream>


namespace bullet_sim {

namespace {

constexpr double kClearancePeriod = 0.01;  ///< [s] of sim time between clearance samples
constexpr double kSupportCosine = 0.7071;  ///< contacts pushing within 45 degrees of up carry the robot
constexpr double kTimeEpsilon = 1e-9;      ///< [s]

std::string format(const char* pattern, double a, double b = 0, double c = 0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

double tiltOf(const Eigen::Isometry3d& pose) {
  return std::acos(std::clamp(pose.linear()(2, 2), -1.0, 1.0));
}

}  // namespace

ScenarioMonitor::ScenarioMonitor(const ScenarioSpec& spec, const Simulation& simulation,
                                 std::vector<std::string> load_warnings)
    : spec_(spec), robots_(simulation.robotNames()), load_warnings_(std::move(load_warnings)) {
  for (const auto& name : robots_) {
    RobotRecord& record = records_[name];
    record.reached.assign(spec.checks.size(), std::nullopt);
    record.region_distance.assign(spec.checks.size(), INFINITY);
    record.min_clearance = INFINITY;
  }
  std::vector<std::string> problems;
  for (size_t i = 0; i < spec.checks.size(); ++i) {
    const Check& check = spec.checks[i];
    const std::string where = "checks." + std::to_string(i) + "." + checkTypeName(check.type);
    if (!check.robot.empty() && !records_.count(check.robot)) {
      problems.push_back(where + ": no robot [" + check.robot + "] in this run" +
                         didYouMean(check.robot, robots_));
      continue;
    }
    if (check.type != Check::Type::kClearance) continue;
    if (!check.from_lidar) {
      clearance_cap_ = std::max(clearance_cap_, 2 * check.min + 0.5);
      continue;
    }
    for (const auto& name : robots_) {
      const Robot& robot = *simulation.robot(name);
      const bool lidar = !robot.outputs<LaserScan>().empty() || !robot.outputs<PointCloud>().empty() ||
                         !robot.outputs<LegacyPointCloud>().empty();
      if ((check.robot.empty() || check.robot == name) && !lidar)
        problems.push_back(where + ": robot [" + name + "] has no lidar; use from: geometry");
    }
  }
  if (!problems.empty()) throw ScenarioError(SpecError(spec.source, problems).what());
  if (clearance_cap_ > 0) clearance_ = std::make_unique<ClearanceQuery>(simulation.world());
  // The first row is the spawn, before any step; then one every record_period on the grid of its multiples.
  for (const auto& name : robots_) {
    recordPose(simulation, *simulation.robot(name), records_[name]);
    trajectory_.push_back(records_[name].last);
  }
  next_row_ = spec.record_period;
}

ScenarioMonitor::~ScenarioMonitor() = default;

void ScenarioMonitor::afterStep(const Simulation& simulation) {
  const double time = simulation.time();
  trails_.afterStep(simulation);
  const bool row = time + kTimeEpsilon >= next_row_;
  if (row) next_row_ += spec_.record_period;
  const bool clearance = clearance_ && time + kTimeEpsilon >= next_clearance_;
  if (clearance) next_clearance_ = time + kClearancePeriod;
  for (const auto& name : robots_) {
    const Robot* robot = simulation.robot(name);
    if (!robot) continue;  // deleted by the user's nodes
    RobotRecord& record = records_[name];
    recordPose(simulation, *robot, record);
    if (row) trajectory_.push_back(record.last);
    if (clearance) recordClearance(*robot, time, record);
    recordLidar(*robot, record);
    recordContacts(simulation, *robot, record);
  }
}

void ScenarioMonitor::recordPose(const Simulation& simulation, const Robot& robot, RobotRecord& record) {
  const RobotBody& body = robot.body();
  const std::string& root = body.spec().root;
  const Eigen::Isometry3d pose = body.linkPose(root);
  TrajectoryRow row;
  row.time = simulation.time();
  row.robot = robot.name();
  row.x = pose.translation().x();
  row.y = pose.translation().y();
  row.z = pose.translation().z();
  row.yaw = std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
  row.pitch = std::asin(-std::clamp(pose.linear()(2, 0), -1.0, 1.0));
  row.roll = std::atan2(pose.linear()(2, 1), pose.linear()(2, 2));
  const Eigen::Vector3d velocity = body.linkLinearVelocity(root);
  row.v = velocity.x() * std::cos(row.yaw) + velocity.y() * std::sin(row.yaw);
  row.w = body.linkAngularVelocity(root).z();
  if (record.last.robot == robot.name())
    record.distance += std::hypot(row.x - record.last.x, row.y - record.last.y);
  record.last = row;
  record.max_tilt = std::max(record.max_tilt, tiltOf(pose));
  for (size_t i = 0; i < spec_.checks.size(); ++i) {
    if (spec_.checks[i].type != Check::Type::kReach) continue;
    const double distance = spec_.checks[i].region.distance(row.x, row.y);
    record.region_distance[i] = std::min(record.region_distance[i], distance);
    if (distance == 0 && !record.reached[i]) record.reached[i] = row.time;
  }
}

void ScenarioMonitor::recordClearance(const Robot& robot, double time, RobotRecord& record) {
  const Clearance nearest = clearance_->nearest(robot.body(), std::min(record.min_clearance, clearance_cap_));
  if (nearest.obstacle.empty() || nearest.distance >= record.min_clearance) return;
  record.min_clearance = nearest.distance;
  record.clearance_obstacle = nearest.obstacle;
  record.clearance_time = time;
}

namespace {

/// The ranges [m] a scan or cloud measured; a hit closer than a scan's range_min counts as range_min.
std::vector<double> measuredRanges(const LaserScan& scan) {
  std::vector<double> ranges;
  for (const float range : scan.ranges) {
    if (range == INFINITY || std::isnan(range)) continue;
    ranges.push_back(range == -INFINITY ? scan.range_min : range);
  }
  return ranges;
}

std::vector<double> measuredRanges(const PointCloud& cloud) {
  std::vector<double> ranges;
  for (const Eigen::Vector3f& point : cloud.points) ranges.push_back(point.norm());
  return ranges;
}

}  // namespace

template <class Sample>
void ScenarioMonitor::recordRanges(const Robot& robot, RobotRecord& record) {
  for (const RobotOutput<Sample>& output : robot.outputs<Sample>()) {
    uint64_t& seen = scans_seen_[robot.name() + "/" + output.plugin->name() + "/" + output.topic];
    if (output.stream->count() == seen) continue;
    seen = output.stream->count();
    const Sample& scan = output.stream->latest();
    for (const double measured : measuredRanges(scan)) {
      if (!record.min_lidar_range || measured < *record.min_lidar_range) {
        record.min_lidar_range = measured;
        record.lidar_time = scan.stamp;  // cast behind physics (not in lockstep), it is read some steps later
      }
    }
  }
}

void ScenarioMonitor::recordLidar(const Robot& robot, RobotRecord& record) {
  recordRanges<LaserScan>(robot, record);
  recordRanges<PointCloud>(robot, record);
  recordRanges<LegacyPointCloud>(robot, record);
}

void ScenarioMonitor::recordContacts(const Simulation& simulation, const Robot& robot, RobotRecord& record) {
  const RobotBody& body = robot.body();
  for (const RobotPart& part : body.parts()) {
    for (const CollisionSource& source : part.sources) {
      for (const CollisionContact& contact : body.contacts(source)) {
        if (contact.other.rfind(robot.name() + "::", 0) == 0) continue;  // itself
        const bool support =
            std::all_of(contact.points.begin(), contact.points.end(),
                        [](const ContactPoint& point) { return point.normal.z() > kSupportCosine; });
        if (support) continue;
        record.collision_time += simulation.stepSize();
        if (!record.first_collision) {
          record.first_collision = simulation.time();
          record.first_collision_with = contact.other;
        }
        return;  // one step in contact counts once
      }
    }
  }
}

std::vector<CheckResult> ScenarioMonitor::results() const {
  std::vector<CheckResult> results;
  for (size_t i = 0; i < spec_.checks.size(); ++i) {
    for (const auto& name : robots_) {
      if (spec_.checks[i].robot.empty() || spec_.checks[i].robot == name)
        results.push_back(evaluate(spec_.checks[i], i, name));
    }
  }
  return results;
}

CheckResult ScenarioMonitor::evaluate(const Check& check, size_t index, const std::string& robot) const {
  const RobotRecord& record = records_.at(robot);
  CheckResult result{checkTypeName(check.type), robot, false, std::nullopt, "", 0, "<=", ""};
  switch (check.type) {
    case Check::Type::kReach:
      result.value = record.reached[index];
      result.unit = "s";
      result.limit = check.by;
      result.passed = record.reached[index] && *record.reached[index] <= check.by + kTimeEpsilon;
      result.detail =
          record.reached[index]
              ? format("entered the region at t = %.3f s", *record.reached[index])
              : format("never entered the region; nearest %.3f m from it", record.region_distance[index]);
      break;
    case Check::Type::kClearance: {
      const bool lidar = check.from_lidar;
      const double measured = lidar ? record.min_lidar_range.value_or(INFINITY) : record.min_clearance;
      result.value = std::isfinite(measured) ? std::optional<double>(measured) : std::nullopt;
      if (!lidar && !std::isfinite(measured)) result.value = clearance_cap_;
      result.unit = "m";
      result.limit = check.min;
      result.comparison = ">=";
      result.passed = !result.value || *result.value >= check.min;
      result.detail =
          lidar ? (record.min_lidar_range
                       ? format("nearest lidar range %.3f m at t = %.3f s", measured, record.lidar_time)
                       : "the lidar saw nothing within its range")
                : (record.clearance_obstacle.empty()
                       ? format("nothing within %.3f m", clearance_cap_)
                       : format("nearest %.3f m at t = %.3f s, to ", measured, record.clearance_time) + "[" +
                             record.clearance_obstacle + "]");
      break;
    }
    case Check::Type::kNoCollision:
      result.value = record.collision_time;
      result.unit = "s";
      result.passed = !record.first_collision;
      result.detail = record.first_collision
                          ? format("first touched at t = %.3f s: ", *record.first_collision) + "[" +
                                record.first_collision_with + "]"
                          : "touched nothing but the ground";
      break;
    case Check::Type::kUpright:
      result.value = record.max_tilt;
      result.unit = "rad";
      result.limit = check.max_tilt;
      result.passed = record.max_tilt <= check.max_tilt;
      result.detail = format("tilted at most %.2f degrees", record.max_tilt * 180 / M_PI);
      break;
    case Check::Type::kFinalPose: {
      const double error = std::hypot(record.last.x - check.x, record.last.y - check.y);
      const double yaw_error = std::abs(std::remainder(record.last.yaw - check.yaw, 2 * M_PI));
      result.value = error;
      result.unit = "m";
      result.limit = check.position_tolerance;
      result.passed =
          error <= check.position_tolerance && (!check.check_yaw || yaw_error <= check.yaw_tolerance);
      result.detail =
          format("ended at x %.3f, y %.3f, yaw %.3f", record.last.x, record.last.y, record.last.yaw) +
          format("; %.3f m and %.3f rad off", error, yaw_error);
      break;
    }
    case Check::Type::kNoLoadWarnings:
      result.value = static_cast<double>(load_warnings_.size());
      result.unit = "warnings";
      result.passed = load_warnings_.empty();
      result.detail =
          load_warnings_.empty() ? "loaded without a warning" : "first: " + load_warnings_.front();
      break;
  }
  return result;
}

}  // namespace bullet_sim
