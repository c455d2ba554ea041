#include "bullet_sim/plugins/input_checks.h"

#include <string>
#include <vector>

#include "bullet_sim/common/request_values.h"

namespace bullet_sim {

namespace {

void checkValues(const std::vector<double>& values, const std::string& field, const std::string& unit) {
  for (size_t i = 0; i < values.size(); ++i)
    requireWithin(values[i], kMaxCommand, field + "[" + std::to_string(i) + "]", unit);
}

void checkTolerances(const std::vector<JointTolerance>& tolerances, const std::string& field) {
  for (size_t i = 0; i < tolerances.size(); ++i) {
    const std::string at = field + "[" + std::to_string(i) + "]";
    requireFinite(tolerances[i].position, at + ".position");
    requireFinite(tolerances[i].velocity, at + ".velocity");
    requireFinite(tolerances[i].acceleration, at + ".acceleration");
  }
}

}  // namespace

void checkInput(const Twist& twist) {
  requireWithin(twist.linear, kMaxCommand, "linear", "m/s");
  requireWithin(twist.angular, kMaxCommand, "angular", "rad/s");
}

void checkInput(const JointTrajectory& trajectory) {
  requireFinite(trajectory.stamp, "header.stamp");
  for (size_t k = 0; k < trajectory.points.size(); ++k) {
    const TrajectoryPoint& point = trajectory.points[k];
    const std::string at = "points[" + std::to_string(k) + "].";
    checkValues(point.positions, at + "positions", "");
    checkValues(point.velocities, at + "velocities", "");
    checkValues(point.accelerations, at + "accelerations", "");
    checkValues(point.effort, at + "effort", "");
    requireFinite(point.time_from_start, at + "time_from_start");
  }
}

void checkInput(const Float64Command& command) { requireWithin(command.data, kMaxCommand, "data", ""); }

void checkInput(const Float64ArrayCommand& command) { checkValues(command.data, "data", ""); }

void checkInput(const FollowJointTrajectoryAction::Goal& goal) {
  checkInput(goal.trajectory);
  checkTolerances(goal.path_tolerance, "path_tolerance");
  checkTolerances(goal.goal_tolerance, "goal_tolerance");
  requireFinite(goal.goal_time_tolerance, "goal_time_tolerance");
}

}  // namespace bullet_sim
