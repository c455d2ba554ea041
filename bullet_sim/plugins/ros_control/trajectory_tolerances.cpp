#include "plugins/ros_control/trajectory_tolerances.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bullet_sim/common/diagnostics.h"

namespace bullet_sim {

namespace {

bool within(double error, double tolerance) { return !(tolerance > 0 && !(std::abs(error) <= tolerance)); }

double nonNegative(const ParameterTree& tree, const std::string& path, double fallback) {
  const double value = tree.number(path, fallback);
  if (!(value >= 0)) {
    throw std::invalid_argument("constraints/" + path + " must be >= 0 (0 is not enforced), not " +
                                tree.describe(path));
  }
  return value;
}

/// A message tolerance over a default: > 0 replaces it, < 0 lifts it, 0 keeps it.
void update(double given, double& tolerance) {
  if (given > 0) tolerance = given;
  if (given < 0) tolerance = 0;
}

void update(const JointTolerance& given, StateTolerances& tolerances) {
  update(given.position, tolerances.position);
  update(given.velocity, tolerances.velocity);
  update(given.acceleration, tolerances.acceleration);
}

}  // namespace

bool withinTolerances(const JointMotion& error, const StateTolerances& tolerances) {
  return within(error.position, tolerances.position) && within(error.velocity, tolerances.velocity) &&
         within(error.acceleration, tolerances.acceleration);
}

std::vector<JointTolerances> readConstraints(const ParameterTree& constraints,
                                             const std::vector<std::string>& joints,
                                             const std::string& controller,
                                             std::vector<std::string>* warnings) {
  const double stopped_velocity = nonNegative(constraints, "stopped_velocity_tolerance", 0.01);
  const double goal_time = nonNegative(constraints, "goal_time", 0);
  std::vector<JointTolerances> tolerances(joints.size());
  for (size_t i = 0; i < joints.size(); ++i) {
    tolerances[i].path.position = nonNegative(constraints, joints[i] + "/trajectory", 0);
    tolerances[i].goal.position = nonNegative(constraints, joints[i] + "/goal", 0);
    tolerances[i].goal.velocity = stopped_velocity;
    tolerances[i].goal_time = goal_time;
  }
  std::vector<std::string> known = joints;
  known.insert(known.end(), {"goal_time", "stopped_velocity_tolerance"});
  for (const auto& key : constraints.keys()) {
    if (std::count(known.begin(), known.end(), key) == 0 && warnings) {
      warnings->push_back("controller [" + controller + "]: constraints/" + key +
                          " is neither one of its joints nor goal_time or stopped_velocity_tolerance" +
                          didYouMean(key, known) + ": ignored");
    }
  }
  for (const auto& joint : joints) {
    for (const auto& key : constraints.at(joint).keys()) {
      if (key != "trajectory" && key != "goal" && warnings) {
        warnings->push_back("controller [" + controller + "]: constraints/" + joint + "/" + key +
                            " is not a tolerance joint_trajectory_controller reads (trajectory, goal)" +
                            didYouMean(key, {"trajectory", "goal"}) + ": ignored");
      }
    }
  }
  return tolerances;
}

std::vector<JointTolerances> goalTolerances(const FollowJointTrajectoryAction::Goal& goal,
                                            const std::vector<std::string>& joints,
                                            std::vector<JointTolerances> defaults) {
  for (size_t i = 0; i < joints.size() && i < defaults.size(); ++i) {
    for (const auto& given : goal.path_tolerance) {
      if (given.name == joints[i]) update(given, defaults[i].path);
    }
    for (const auto& given : goal.goal_tolerance) {
      if (given.name == joints[i]) update(given, defaults[i].goal);
    }
    update(goal.goal_time_tolerance, defaults[i].goal_time);
  }
  return defaults;
}

}  // namespace bullet_sim
