#include "plugins/ros_control/joint_trajectory.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bullet_sim/common/diagnostics.h"

namespace bullet_sim {

namespace {

bool allFinite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double value) { return std::isfinite(value); });
}

/// Every waypoint gives one position per joint (and velocities and accelerations, if any, as many), all
/// finite, at strictly increasing times.
void checkWaypoints(const JointTrajectory& message) {
  const size_t joints = message.joint_names.size();
  for (size_t k = 0; k < message.points.size(); ++k) {
    const TrajectoryPoint& point = message.points[k];
    std::ostringstream where;
    where << "waypoint " << k << " of " << message.points.size() << " ";
    for (const auto& [name, values, required] :
         {std::make_tuple("positions", &point.positions, true),
          std::make_tuple("velocities", &point.velocities, false),
          std::make_tuple("accelerations", &point.accelerations, false)}) {
      if ((required || !values->empty()) && values->size() != joints) {
        throw std::invalid_argument(where.str() + "has " + std::to_string(values->size()) + " " + name +
                                    " for " + std::to_string(joints) + " joints");
      }
      if (!allFinite(*values))
        throw std::invalid_argument(where.str() + "has " + name + " that are not numbers");
    }
    if (!std::isfinite(point.time_from_start))
      throw std::invalid_argument(where.str() + "has no finite time_from_start");
    if (k > 0 && !(point.time_from_start > message.points[k - 1].time_from_start)) {
      throw std::invalid_argument(
          "the waypoints' time_from_start must increase strictly from one waypoint to the next (waypoint " +
          std::to_string(k) + " is not after waypoint " + std::to_string(k - 1) + ")");
    }
  }
}

/// Joint `m` of a waypoint, its position shifted by `offset`.
Knot knotOf(const TrajectoryPoint& point, size_t m, double offset) {
  Knot knot{point.positions[m] + offset, std::nullopt, std::nullopt};
  if (!point.velocities.empty()) knot.velocity = point.velocities[m];
  if (!point.accelerations.empty()) knot.acceleration = point.accelerations[m];
  return knot;
}

/// The index of the first waypoint after `time`, given that the message starts at `start`.
size_t firstWaypointAfter(const JointTrajectory& message, double start, double time) {
  for (size_t k = 0; k < message.points.size(); ++k) {
    if (start + message.points[k].time_from_start > time) return k;
  }
  std::ostringstream why;
  why << "all " << message.points.size() << " waypoints are in the past: the last one was "
      << time - (start + message.points.back().time_from_start) << " s before the controller's next update";
  throw std::invalid_argument(why.str());
}

/// One joint's new segments: what runs until `handover`, then a segment to the waypoint `first`, then the
/// rest.
JointSegments mergeJoint(const JointTrajectory& message, size_t m, size_t first, double start, double time,
                         const JointSegments& current, bool continuous, GoalId goal,
                         const JointTolerances& tolerances) {
  const double handover = std::max(start, time);
  const JointMotion there = sample(current, handover);
  const TrajectoryPoint& next = message.points[first];
  const double offset = wraparoundOffset(there.position, next.positions[m], continuous);
  const auto running = std::find_if(current.rbegin(), current.rend(), [&](const TrajectorySegment& segment) {
                         return segment.spline.startTime() <= time;
                       }).base();
  const auto last = std::find_if(current.rbegin(), current.rend(), [&](const TrajectorySegment& segment) {
                      return segment.spline.startTime() <= handover;
                    }).base();
  if (running == current.begin() || last == current.begin())
    throw std::invalid_argument("the running trajectory starts after the new one: cannot join them");
  JointSegments segments(std::prev(running), last);
  const Knot from{there.position, there.velocity, there.acceleration};
  segments.push_back({SplineSegment(handover, from, start + next.time_from_start, knotOf(next, m, offset)), 0,
                      goal, tolerances});
  for (size_t k = first; k + 1 < message.points.size(); ++k) {
    const TrajectoryPoint& a = message.points[k];
    const TrajectoryPoint& b = message.points[k + 1];
    segments.push_back({SplineSegment(start + a.time_from_start, knotOf(a, m, offset),
                                      start + b.time_from_start, knotOf(b, m, offset)),
                        a.time_from_start, goal, tolerances});
  }
  return segments;
}

}  // namespace

const TrajectorySegment* findSegment(const JointSegments& segments, double time) {
  const auto after = std::upper_bound(
      segments.begin(), segments.end(), time,
      [](double t, const TrajectorySegment& segment) { return t < segment.spline.startTime(); });
  return after == segments.begin() ? nullptr : &*std::prev(after);
}

JointMotion sample(const JointSegments& segments, double time) {
  if (const TrajectorySegment* segment = findSegment(segments, time)) return segment->spline.sample(time);
  return segments.empty() ? JointMotion{} : segments.front().spline.sample(time);
}

double wraparoundOffset(double previous, double next, bool continuous) {
  if (!continuous) return 0;
  double distance = std::remainder(next - previous, 2 * M_PI);
  if (std::abs(std::abs(distance) - M_PI) < 1e-9)
    distance = next > previous ? std::abs(distance) : -std::abs(distance);
  return previous + distance - next;
}

std::vector<size_t> jointMapping(const std::vector<std::string>& names,
                                 const std::vector<std::string>& joints, bool allow_partial) {
  std::vector<size_t> mapping;
  for (const auto& name : names) {
    const auto found = std::find(joints.begin(), joints.end(), name);
    if (found == joints.end()) {
      throw std::invalid_argument("joint [" + name + "] is not one of the controller's" +
                                  didYouMean(name, joints));
    }
    const size_t index = found - joints.begin();
    if (std::count(mapping.begin(), mapping.end(), index))
      throw std::invalid_argument("joint [" + name + "] is named twice");
    mapping.push_back(index);
  }
  if (!allow_partial && mapping.size() != joints.size()) {
    throw std::invalid_argument("the trajectory names " + std::to_string(names.size()) +
                                " of the controller's " + std::to_string(joints.size()) +
                                " joints, and allow_partial_joints_goal is false: name them all");
  }
  return mapping;
}

std::vector<JointSegments> mergeTrajectory(const JointTrajectory& message, double time,
                                           const TrajectoryMerge& merge) {
  if (message.points.empty()) throw std::invalid_argument("the trajectory has no waypoints");
  const std::vector<size_t> mapping = jointMapping(message.joint_names, merge.joints, merge.allow_partial);
  checkWaypoints(message);
  const double start = message.stamp == 0 ? time : message.stamp;
  const size_t first = firstWaypointAfter(message, start, time);
  std::vector<JointSegments> result = merge.current;
  for (auto& segments :
       result) {  // joints it does not name keep theirs, from the running segment on serving its goal
    const TrajectorySegment* running = findSegment(segments, time);
    for (auto& segment : segments) {
      if (running && &segment >= running) segment.goal = merge.goal;
    }
  }
  for (size_t m = 0; m < mapping.size(); ++m) {
    const size_t j = mapping[m];
    const JointTolerances tolerances = merge.tolerances.empty() ? JointTolerances{} : merge.tolerances.at(j);
    result[j] = mergeJoint(message, m, first, start, time, merge.current.at(j), merge.continuous.at(j),
                           merge.goal, tolerances);
  }
  return result;
}

std::vector<JointSegments> holdTrajectory(const std::vector<double>& positions, double time, GoalId goal) {
  std::vector<JointSegments> result;
  for (double position : positions) {
    const Knot rest{position, 0.0, 0.0};
    result.push_back({{SplineSegment(time, rest, time, rest), 0, goal, {}}});
  }
  return result;
}

std::vector<JointSegments> stopTrajectory(const std::vector<JointMotion>& desired, double time,
                                          double duration, GoalId goal) {
  std::vector<JointSegments> result;
  for (const JointMotion& motion : desired) {
    const Knot start{motion.position, motion.velocity, 0.0};
    const SplineSegment there_and_back(time, start, time + 2 * duration,
                                       {motion.position, -motion.velocity, 0.0});
    const JointMotion stop = there_and_back.sample(time + duration);
    const Knot end{stop.position, stop.velocity, stop.acceleration};
    result.push_back({{SplineSegment(time, start, time + duration, end), 0, goal, {}}});
  }
  return result;
}

}  // namespace bullet_sim
