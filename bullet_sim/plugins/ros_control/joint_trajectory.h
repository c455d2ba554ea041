// What a joint trajectory controller follows, as ros_controllers' joint_trajectory_controller (Noetic) builds
// it: per joint, spline segments sorted by start time, each serving an action goal (or none) with that goal's
// tolerances. A new trajectory replaces the old one from its first waypoint on: the old one runs until then,
// and a segment from where it is then leads to that waypoint.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/actions.h"
#include "bullet_sim/plugins/outputs.h"
#include "plugins/ros_control/spline_segment.h"
#include "plugins/ros_control/trajectory_tolerances.h"

namespace bullet_sim {

/// A segment of one joint's trajectory, and the goal it serves.
struct TrajectorySegment {
  SplineSegment spline;
  double time_from_start = 0;  ///< [s] of its first waypoint in its trajectory
  GoalId goal = 0;             ///< the action goal it serves; 0 for a command or a hold
  JointTolerances tolerances;  ///< checked while its goal is the active one
};

/// One joint's trajectory: segments sorted by start time; the last one started runs.
using JointSegments = std::vector<TrajectorySegment>;

/// The segment running at `time` [s]: the last that started at or before it; nullptr before them all.
const TrajectorySegment* findSegment(const JointSegments& segments, double time);
/// The motion at `time` [s] along `segments`: their first one's start before they begin.
JointMotion sample(const JointSegments& segments, double time);

/// ros_controllers' wraparoundJointOffset: what to add to `next` [rad] so that a continuous joint at
/// `previous` reaches it the short way round; 0 for other joints.
double wraparoundOffset(double previous, double next, bool continuous);

/// For each joint a message names, the index of that joint among `joints`. Throws std::invalid_argument when
/// a name is not one of them or is repeated, or (unless `allow_partial`) when not every joint is named.
std::vector<size_t> jointMapping(const std::vector<std::string>& names,
                                 const std::vector<std::string>& joints, bool allow_partial);

/// What a new trajectory is merged with.
struct TrajectoryMerge {
  const std::vector<std::string>& joints;     ///< the controller's, in its order
  const std::vector<bool>& continuous;        ///< per joint: it wraps around
  const std::vector<JointSegments>& current;  ///< what runs now, per joint
  GoalId goal = 0;                            ///< the goal the new trajectory serves; 0 for a command
  std::vector<JointTolerances> tolerances;    ///< per joint, for a goal's segments (empty: none enforced)
  bool allow_partial = false;                 ///< the message may name some of the joints only
};

/// ros_controllers' initJointTrajectory: the trajectory once `message` is taken at `time` [s] (the next
/// update). The message starts at its stamp, or at `time` when the stamp is 0; its waypoints not after `time`
/// are dropped. What runs now keeps running until the message's start (or `time`, if later); from there a
/// segment leads to the first waypoint kept, then the message's waypoints follow. Joints it does not name
/// keep their trajectory. Throws std::invalid_argument saying why the message cannot be followed.
std::vector<JointSegments> mergeTrajectory(const JointTrajectory& message, double time,
                                           const TrajectoryMerge& merge);

/// A segment per joint that holds `positions` from `time` [s] on, serving `goal`.
std::vector<JointSegments> holdTrajectory(const std::vector<double>& positions, double time, GoalId goal);
/// ros_controllers' stop trajectory: from `desired` (positions and velocities) at `time` [s] to rest within
/// `duration` [s], serving `goal`: each joint follows the first half of the quintic that leaves with the
/// desired velocity and returns to the same position with the opposite one in twice the time.
std::vector<JointSegments> stopTrajectory(const std::vector<JointMotion>& desired, double time,
                                          double duration, GoalId goal);

}  // namespace bullet_sim
