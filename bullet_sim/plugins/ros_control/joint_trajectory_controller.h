// position_controllers/JointTrajectoryController, velocity_controllers/JointTrajectoryController and
// effort_controllers/JointTrajectoryController (ros_controllers' joint_trajectory_controller, Noetic),
// ROS-free. It moves its joints along trajectories (joint_trajectory.h) that arrive on <name>/command
// (trajectory_msgs/JointTrajectory) or as goals of the <name>/follow_joint_trajectory action
// (control_msgs/FollowJointTrajectory); a new one replaces the one running from its first waypoint on. While
// a goal runs, each joint must stay within its path tolerance, else the goal aborts with
// PATH_TOLERANCE_VIOLATED; it succeeds once every joint ends within its goal tolerance, or aborts with
// GOAL_TOLERANCE_VIOLATED when one has not within goal_time after the end. It publishes
// control_msgs/JointTrajectoryControllerState on <name>/state and serves <name>/query_state
// (control_msgs/QueryTrajectoryState).
//
// Parameters, with ros_controllers' defaults:
//   joints                      the joints, required
//   constraints                 goal_time, stopped_velocity_tolerance, <joint>/trajectory, <joint>/goal
//                               (trajectory_tolerances.h)
//   gains/<joint>               p (required), i, d, i_clamp, ... (control_toolbox's Pid): velocity and effort
//                               variants only, which command p e + i integral(e) + d e' on the position error
//                               e
//   velocity_ff/<joint> [0]     velocity and effort variants: adds this times the desired velocity
//   state_publish_rate [50 Hz]  0 publishes no state
//   action_monitor_rate [20 Hz] how often a goal's feedback is sent, and its success reported
//   stop_trajectory_duration [0 s]  how a stop (a start, a cancel, an empty trajectory) comes to rest: 0
//   holds
//                               where the joints are, more ramps the desired motion down to rest in that time
//   allow_partial_joints_goal [false]  whether a trajectory may name some of the joints only
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "plugins/ros_control/controller.h"
#include "plugins/ros_control/joint_trajectory.h"
#include "plugins/ros_control/pid.h"

namespace bullet_sim {

class JointTrajectoryController : public Controller {
 public:
  using Action = FollowJointTrajectoryAction;

  /// The variant commanding joints through `interface`.
  JointTrajectoryController(const ControllerSetup& setup, JointInterface interface);

  const std::vector<std::string>& joints() const { return names_; }
  /// The active goal; 0 when none runs.
  GoalId activeGoal() const { return active_goal_; }
  /// Where the joints should be, are, and the difference, as of the last update.
  const JointTrajectoryControllerState& state() const { return state_; }
  std::string following() const override;

 protected:
  void starting(double time) override;
  void stopping(double time) override;
  void onUpdate(double time, double period) override;
  void onReset() override;

 private:
  void readParameters(const ControllerSetup& setup, JointInterface interface);
  void readGains(const ControllerSetup& setup);
  void declarePorts();

  // What the ports take.
  std::string takeCommand(const JointTrajectory& trajectory);
  GoalDecision<Action> takeGoal(GoalId goal, const Action::Goal& request);
  void cancelGoal(GoalId goal);
  std::string queryState(const QueryTrajectoryStateRequest& request,
                         QueryTrajectoryStateRequest::Reply& reply) const;

  /// Follows `trajectory` from the next update on, serving `goal`; "" or why it cannot be followed.
  std::string replaceTrajectory(const JointTrajectory& trajectory, GoalId goal,
                                const std::vector<JointTolerances>& tolerances);
  /// Comes to rest from `time` on (stop_trajectory_duration), serving `goal`.
  void hold(double time, GoalId goal);
  /// Ends the active goal as canceled (preempted), if there is one.
  void preemptActiveGoal();
  /// Ends the active goal with `end` and a result; a success is reported at the next monitor tick.
  void finishActiveGoal(GoalEnd end, int error_code, const std::string& error_string);

  // One update, in ros_controllers' order.
  void sampleStates(double time);
  void checkTolerances(double time);
  void commandJoints(double period);
  void report(double time);

  std::vector<HardwareJoint*> joints_;
  std::vector<std::string> names_;
  std::vector<bool> continuous_;
  JointInterface interface_;
  std::vector<JointTolerances> default_tolerances_;
  std::vector<Pid> pids_;            ///< velocity and effort variants
  std::vector<double> velocity_ff_;  ///< velocity and effort variants
  double state_period_ = 0.02;       ///< [s]; 0: no state
  double monitor_period_ = 0.05;     ///< [s]
  double stop_duration_ = 0;         ///< [s]
  bool allow_partial_ = false;

  std::vector<JointSegments> trajectory_;
  std::vector<JointMotion> desired_, actual_, error_;
  double time_from_start_ = 0;  ///< [s] of the desired motion, along the running trajectory
  double segment_start_ = 0;    ///< [s] when the first joint's running segment started
  double last_time_ = 0;        ///< [s] of the last update (or the start)
  double last_period_ = 0;      ///< [s] of the last update
  GoalId active_goal_ = 0;
  std::vector<bool> goal_reached_;  ///< per joint, for the active goal
  std::vector<GoalId> succeeded_;   ///< goals that succeeded, reported at the next monitor tick
  double last_state_ = 0;           ///< [s] when the state was last due
  double last_monitor_ = 0;         ///< [s] of the last monitor tick

  JointTrajectoryControllerState state_;
  Stream<JointTrajectoryControllerState> state_stream_;
  std::shared_ptr<GoalReports<Action>> reports_ = std::make_shared<GoalReports<Action>>();
};

}  // namespace bullet_sim
