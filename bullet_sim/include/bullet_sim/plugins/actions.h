// What plugins' actions take and report, in actionlib terms but without ROS. The node numbers each goal it
// hands a plugin; the plugin accepts or rejects it at once, then reports feedback and, once, how the goal
// ended. The node maps each action type to its actionlib server once.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bullet_sim/plugins/outputs.h"

namespace bullet_sim {

/// Which goal: the node numbers the goals it hands a plugin from 1; 0 is no goal.
using GoalId = uint64_t;

/// How a goal ends, as actionlib's ServerGoalHandle ends it (a canceled goal that was active is PREEMPTED).
enum class GoalEnd { kSucceeded, kAborted, kCanceled };

/// control_msgs/JointTolerance: for each, > 0 is the tolerance, < 0 lifts it, 0 keeps the controller's.
struct JointTolerance {
  std::string name;
  double position = 0;      ///< [rad] or [m]
  double velocity = 0;      ///< [rad/s] or [m/s]
  double acceleration = 0;  ///< [rad/s^2] or [m/s^2]
};

/// control_msgs/FollowJointTrajectory.
struct FollowJointTrajectoryAction {
  struct Goal {
    JointTrajectory trajectory;
    std::vector<JointTolerance> path_tolerance;
    std::vector<JointTolerance> goal_tolerance;
    double goal_time_tolerance = 0;  ///< [s]; > 0 replaces the controller's, < 0 lifts it, 0 keeps it
  };
  using Feedback = JointTrajectoryControllerState;
  struct Result {
    static constexpr int kSuccessful = 0;
    static constexpr int kInvalidGoal = -1;
    static constexpr int kInvalidJoints = -2;
    static constexpr int kOldHeaderTimestamp = -3;
    static constexpr int kPathToleranceViolated = -4;
    static constexpr int kGoalToleranceViolated = -5;
    int error_code = kSuccessful;
    std::string error_string;
  };
};

/// A goal's verdict when it arrives.
template <class Action>
struct GoalDecision {
  bool accepted = false;
  typename Action::Result result;  ///< why it was rejected
};

/// What a plugin reports of its goals, in order, until the node takes it: feedback (only the latest of a goal
/// waits) and each goal's end with its result.
template <class Action>
class GoalReports {
 public:
  struct Report {
    GoalId goal = 0;
    std::optional<GoalEnd> end;  ///< nullopt for feedback
    typename Action::Feedback feedback;
    typename Action::Result result;
  };

  void feedback(GoalId goal, const typename Action::Feedback& feedback) {
    for (auto& report : pending_) {
      if (report.goal == goal && !report.end) {
        report.feedback = feedback;
        return;
      }
    }
    pending_.push_back({goal, std::nullopt, feedback, {}});
  }
  void finish(GoalId goal, GoalEnd end, const typename Action::Result& result) {
    pending_.push_back({goal, end, {}, result});
  }
  /// The reports since the last call, oldest first.
  std::vector<Report> take() { return std::exchange(pending_, {}); }
  bool empty() const { return pending_.empty(); }

 private:
  std::vector<Report> pending_;
};

}  // namespace bullet_sim
