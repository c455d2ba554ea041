#include "plugins/ros_control/joint_trajectory_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bullet_sim/common/diagnostics.h"

namespace bullet_sim {

namespace {

using Result = FollowJointTrajectoryAction::Result;

/// 1 / rate [s] of a rate parameter [Hz] that must be > 0 (or >= 0 with `zero_allowed`, 0 giving 0).
double periodOf(const ParameterTree& parameters, const std::string& name, double fallback,
                bool zero_allowed) {
  const double rate = parameters.number(name, fallback);
  if (zero_allowed && rate == 0) return 0;
  if (!(rate > 0) || !std::isfinite(rate)) {
    throw std::invalid_argument(name + " must be " + (zero_allowed ? ">= 0" : "> 0") + " [Hz], not " +
                                parameters.describe(name));
  }
  return 1 / rate;
}

/// One warning for each key under `parameters`' `group` that is not one of `joints`.
void warnOtherJoints(const ControllerSetup& setup, const std::string& group,
                     const std::vector<std::string>& joints) {
  for (const auto& key : setup.parameters.at(group).keys()) {
    if (std::count(joints.begin(), joints.end(), key) == 0) {
      setup.warnings.push_back("controller [" + setup.name + "]: " + group + "/" + key +
                               " is not one of its joints" + didYouMean(key, joints) + ": ignored");
    }
  }
}

/// The positions, velocities or accelerations of `motions`.
std::vector<double> column(const std::vector<JointMotion>& motions, double JointMotion::*member) {
  std::vector<double> values;
  for (const auto& motion : motions) values.push_back(motion.*member);
  return values;
}

}  // namespace

JointTrajectoryController::JointTrajectoryController(const ControllerSetup& setup, JointInterface interface)
    : Controller(setup, interfaceName(interface)), interface_(interface) {
  readParameters(setup, interface);
  if (interface != JointInterface::kPosition) readGains(setup);
  declarePorts();
}

void JointTrajectoryController::readParameters(const ControllerSetup& setup, JointInterface interface) {
  const ParameterTree& parameters = setup.parameters;
  std::vector<std::string> known = {"joints",
                                    "constraints",
                                    "state_publish_rate",
                                    "action_monitor_rate",
                                    "stop_trajectory_duration",
                                    "allow_partial_joints_goal"};
  if (interface != JointInterface::kPosition) known.insert(known.end(), {"gains", "velocity_ff"});
  warnUnread(setup, known);
  names_ = parameters.texts("joints");
  if (names_.empty()) throw std::invalid_argument("joints is not set: give the joints the trajectories move");
  for (const auto& name : names_) {
    if (std::count(names_.begin(), names_.end(), name) > 1)
      throw std::invalid_argument("joints names [" + name + "] twice");
    joints_.push_back(&claim(name, interface));
    continuous_.push_back(joints_.back()->spec->type == JointSpec::Type::kContinuous);
  }
  state_period_ = periodOf(parameters, "state_publish_rate", 50, /*zero_allowed=*/true);
  monitor_period_ = periodOf(parameters, "action_monitor_rate", 20, /*zero_allowed=*/false);
  stop_duration_ = parameters.number("stop_trajectory_duration", 0);
  if (!(stop_duration_ >= 0) || !std::isfinite(stop_duration_)) {
    throw std::invalid_argument("stop_trajectory_duration must be >= 0 [s], not " +
                                parameters.describe("stop_trajectory_duration"));
  }
  allow_partial_ = parameters.flag("allow_partial_joints_goal", false);
  default_tolerances_ = readConstraints(parameters.at("constraints"), names_, name(), &setup.warnings);
  const size_t n = names_.size();
  desired_.assign(n, {});
  actual_.assign(n, {});
  error_.assign(n, {});
  goal_reached_.assign(n, false);
  trajectory_ = holdTrajectory(std::vector<double>(n, 0.0), 0, 0);
}

void JointTrajectoryController::readGains(const ControllerSetup& setup) {
  for (const auto& joint : names_) {
    const auto gains = Pid::gainsFrom(setup.parameters.at("gains/" + joint));
    if (!gains) {
      throw std::invalid_argument("gains/" + joint + "/p is not set: " + type() +
                                  " needs PID gains for each joint (p, and i, d, i_clamp as wanted)");
    }
    pids_.emplace_back(*gains);
    velocity_ff_.push_back(setup.parameters.number("velocity_ff/" + joint, 0));
  }
  warnOtherJoints(setup, "gains", names_);
  warnOtherJoints(setup, "velocity_ff", names_);
}

void JointTrajectoryController::declarePorts() {
  state_.joint_names = names_;
  ownPorts().addInput<JointTrajectory>(topic("command"), [this](const JointTrajectory& trajectory, double) {
    return takeCommand(trajectory);
  });
  ownPorts().addOutput(topic("state"), state_stream_);
  ownPorts().addService<QueryTrajectoryStateRequest>(
      topic("query_state"),
      [this](const QueryTrajectoryStateRequest& request, QueryTrajectoryStateRequest::Reply& reply) {
        return queryState(request, reply);
      });
  ActionHandlers<Action> handlers;
  handlers.goal = [this](GoalId goal, const Action::Goal& request, double) {
    return takeGoal(goal, request);
  };
  handlers.cancel = [this](GoalId goal, double) { cancelGoal(goal); };
  handlers.reports = reports_;
  ownPorts().addAction(topic("follow_joint_trajectory"), handlers);
}

void JointTrajectoryController::starting(double time) {
  last_time_ = time;
  last_period_ = 0;
  for (size_t i = 0; i < joints_.size(); ++i) desired_[i] = {joints_[i]->position, joints_[i]->velocity, 0};
  hold(time, 0);
  last_state_ = last_monitor_ = time;
  for (size_t i = 0; i < joints_.size(); ++i) {
    if (interface_ == JointInterface::kPosition) {
      joints_[i]->command = joints_[i]->position;
    } else {
      pids_[i].reset();
      joints_[i]->command = 0;
    }
  }
}

std::string JointTrajectoryController::following() const {
  return active_goal_ == 0 ? "" : "follow_joint_trajectory goal " + std::to_string(active_goal_);
}

void JointTrajectoryController::stopping(double) {
  preemptActiveGoal();
  for (GoalId goal : std::exchange(succeeded_, {})) reports_->finish(goal, GoalEnd::kSucceeded, {});
}

void JointTrajectoryController::onReset() { stopping(last_time_); }

std::string JointTrajectoryController::takeCommand(const JointTrajectory& trajectory) {
  if (!running()) return "a trajectory for controller [" + name() + "], which is not running";
  const std::string why = replaceTrajectory(trajectory, 0, {});
  if (!why.empty()) return "a trajectory for controller [" + name() + "]: " + why;
  preemptActiveGoal();
  return "";
}

GoalDecision<JointTrajectoryController::Action> JointTrajectoryController::takeGoal(
    GoalId goal, const Action::Goal& request) {
  const auto reject = [&](int code, const std::string& why) {
    return GoalDecision<Action>{false, {code, "controller [" + name() + "]: " + why}};
  };
  if (!running()) return reject(Result::kInvalidGoal, "it is not running, so it takes no goal");
  try {
    jointMapping(request.trajectory.joint_names, names_, allow_partial_);
  } catch (const std::invalid_argument& e) {
    return reject(Result::kInvalidJoints, e.what());
  }
  const std::string why =
      replaceTrajectory(request.trajectory, goal, goalTolerances(request, names_, default_tolerances_));
  if (!why.empty()) return reject(Result::kInvalidGoal, why);
  preemptActiveGoal();
  active_goal_ = goal;
  goal_reached_.assign(names_.size(), false);
  return {true, {}};
}

void JointTrajectoryController::cancelGoal(GoalId goal) {
  if (goal == 0 || goal != active_goal_) return;
  active_goal_ = 0;
  hold(last_time_, 0);
  reports_->finish(goal, GoalEnd::kCanceled, {});
}

std::string JointTrajectoryController::queryState(const QueryTrajectoryStateRequest& request,
                                                  QueryTrajectoryStateRequest::Reply& reply) const {
  if (!running()) return "controller [" + name() + "] is not running: no trajectory to query";
  for (size_t i = 0; i < names_.size(); ++i) {
    const TrajectorySegment* segment = findSegment(trajectory_[i], request.time);
    if (!segment) return "controller [" + name() + "]: the time asked for precedes the trajectory's start";
    const JointMotion motion = segment->spline.sample(request.time);
    reply.position.push_back(motion.position);
    reply.velocity.push_back(motion.velocity);
    reply.acceleration.push_back(motion.acceleration);
  }
  reply.name = names_;
  return "";
}

std::string JointTrajectoryController::replaceTrajectory(const JointTrajectory& trajectory, GoalId goal,
                                                         const std::vector<JointTolerances>& tolerances) {
  if (trajectory.points.empty()) {  // an empty trajectory stops the joints
    hold(last_time_, goal);
    return "";
  }
  try {
    const TrajectoryMerge merge{names_, continuous_, trajectory_, goal, tolerances, allow_partial_};
    trajectory_ = mergeTrajectory(trajectory, last_time_ + last_period_, merge);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

void JointTrajectoryController::hold(double time, GoalId goal) {
  if (stop_duration_ > 0) {
    trajectory_ = stopTrajectory(desired_, time, stop_duration_, goal);
    return;
  }
  std::vector<double> positions;
  for (const HardwareJoint* joint : joints_) positions.push_back(joint->position);
  trajectory_ = holdTrajectory(positions, time, goal);
}

void JointTrajectoryController::preemptActiveGoal() {
  if (active_goal_ == 0) return;
  reports_->finish(std::exchange(active_goal_, 0), GoalEnd::kCanceled, {});
}

void JointTrajectoryController::finishActiveGoal(GoalEnd end, int error_code,
                                                 const std::string& error_string) {
  const GoalId goal = std::exchange(active_goal_, 0);
  goal_reached_.assign(names_.size(), false);
  if (end == GoalEnd::kSucceeded) {
    succeeded_.push_back(goal);
  } else {
    reports_->finish(goal, end, {error_code, error_string});
  }
}

void JointTrajectoryController::onUpdate(double time, double period) {
  last_time_ = time;
  last_period_ = period;
  sampleStates(time);
  checkTolerances(time);
  commandJoints(period);
  report(time);
}

void JointTrajectoryController::sampleStates(double time) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    const TrajectorySegment* segment = findSegment(trajectory_[i], time);
    desired_[i] = segment ? segment->spline.sample(time) : sample(trajectory_[i], time);
    actual_[i] = {joints_[i]->position, joints_[i]->velocity, 0};
    const double difference = desired_[i].position - actual_[i].position;
    error_[i] = {continuous_[i] ? std::remainder(difference, 2 * M_PI) : difference,
                 desired_[i].velocity - actual_[i].velocity, 0};
    if (i == 0 && segment) {
      time_from_start_ = segment->time_from_start;
      segment_start_ = segment->spline.startTime();
    }
  }
}

void JointTrajectoryController::checkTolerances(double time) {
  if (active_goal_ == 0) return;
  for (size_t i = 0; i < joints_.size(); ++i) {
    const TrajectorySegment* segment = findSegment(trajectory_[i], time);
    if (!segment || segment->goal != active_goal_) continue;
    const JointTolerances& tolerances = segment->tolerances;
    if (time < segment->spline.endTime()) {
      if (!withinTolerances(error_[i], tolerances.path)) {
        finishActiveGoal(GoalEnd::kAborted, Result::kPathToleranceViolated,
                         names_[i] + " path error " + std::to_string(error_[i].position));
        return;
      }
    } else if (segment == &trajectory_[i].back()) {
      if (withinTolerances(error_[i], tolerances.goal)) {
        goal_reached_[i] = true;
      } else if (!(time < segment->spline.endTime() + tolerances.goal_time)) {
        finishActiveGoal(GoalEnd::kAborted, Result::kGoalToleranceViolated,
                         names_[i] + " goal error " + std::to_string(error_[i].position));
        return;
      }
    }
  }
  if (std::all_of(goal_reached_.begin(), goal_reached_.end(), [](bool reached) { return reached; }))
    finishActiveGoal(GoalEnd::kSucceeded, Result::kSuccessful, "");
}

void JointTrajectoryController::commandJoints(double period) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    if (interface_ == JointInterface::kPosition) {
      joints_[i]->command = desired_[i].position;
    } else {
      joints_[i]->command = velocity_ff_[i] * desired_[i].velocity +
                            pids_[i].compute(error_[i].position, error_[i].velocity, period);
    }
  }
}

void JointTrajectoryController::report(double time) {
  state_.stamp = time;
  state_.desired = {column(desired_, &JointMotion::position),
                    column(desired_, &JointMotion::velocity),
                    column(desired_, &JointMotion::acceleration),
                    {},
                    time_from_start_};
  const double actual_from_start = time - segment_start_ + time_from_start_;
  state_.actual = {column(actual_, &JointMotion::position),
                   column(actual_, &JointMotion::velocity),
                   {},
                   {},
                   actual_from_start};
  state_.error = {column(error_, &JointMotion::position),
                  column(error_, &JointMotion::velocity),
                  {},
                  {},
                  time_from_start_ - actual_from_start};
  if (time - last_monitor_ >= monitor_period_ - 1e-9) {
    last_monitor_ = time - last_monitor_ < 2 * monitor_period_ ? last_monitor_ + monitor_period_ : time;
    for (GoalId goal : std::exchange(succeeded_, {})) reports_->finish(goal, GoalEnd::kSucceeded, {});
    if (active_goal_ != 0) reports_->feedback(active_goal_, state_);
  }
  if (state_period_ > 0 && last_state_ + state_period_ < time) {
    last_state_ = time - last_state_ < 2 * state_period_ ? last_state_ + state_period_ : time;
    state_stream_.next() = state_;
    state_stream_.publish();
  }
}

}  // namespace bullet_sim
