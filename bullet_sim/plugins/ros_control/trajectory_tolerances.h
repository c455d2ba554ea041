// How far a joint may stray from its trajectory, as ros_controllers' joint_trajectory_controller (Noetic) has
// it: while a segment runs (path), at the end (goal) and for how long after the end the goal may still be
// reached (goal_time). A tolerance of 0 is not enforced.
//
// The controller's defaults come from its `constraints` parameters:
//   constraints:
//     goal_time: 0.5                    # [s], default 0
//     stopped_velocity_tolerance: 0.01  # [rad/s] at the goal, default 0.01
//     <joint>: {trajectory: 0.05, goal: 0.02}   # [rad] or [m], path and goal positions, default 0
// and a FollowJointTrajectory goal may change them per joint.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/parameter_tree.h"
#include "bullet_sim/plugins/actions.h"
#include "plugins/ros_control/spline_segment.h"

namespace bullet_sim {

/// Bounds on |error| of position, velocity and acceleration; 0 is not enforced.
struct StateTolerances {
  double position = 0;
  double velocity = 0;
  double acceleration = 0;
};

/// One joint's tolerances along one goal.
struct JointTolerances {
  StateTolerances path;  ///< while a segment runs
  StateTolerances goal;  ///< at the end
  double goal_time = 0;  ///< [s] after the end in which the goal may still be reached
};

/// Whether `error` (desired - actual) is within `tolerances`.
bool withinTolerances(const JointMotion& error, const StateTolerances& tolerances);

/// The tolerances `constraints` give `joints`, in their order. Keys under it that are neither a known key nor
/// one of the joints go to `warnings`. Throws SpecError for a value of the wrong kind, std::invalid_argument
/// for a negative one.
std::vector<JointTolerances> readConstraints(const ParameterTree& constraints,
                                             const std::vector<std::string>& joints,
                                             const std::string& controller,
                                             std::vector<std::string>* warnings);

/// `defaults` changed by a goal's path and goal tolerances (by joint name) and goal time tolerance: a value >
/// 0 replaces the default, < 0 lifts it (0: not enforced), 0 keeps it.
std::vector<JointTolerances> goalTolerances(const FollowJointTrajectoryAction::Goal& goal,
                                            const std::vector<std::string>& joints,
                                            std::vector<JointTolerances> defaults);

}  // namespace bullet_sim
