// The ROS face of joint trajectories: trajectory_msgs/JointTrajectory in, control_msgs'
// JointTrajectoryControllerState out, the QueryTrajectoryState service and the FollowJointTrajectory action's
// messages (its server is ActionBridge, action_server.h).
#pragma once

#include <control_msgs/FollowJointTrajectoryAction.h>
#include <control_msgs/JointTrajectoryControllerState.h>
#include <ros/ros.h>
#include <trajectory_msgs/JointTrajectory.h>

#include "bullet_sim/plugins/ports.h"

namespace bullet_sim {

JointTrajectory toTrajectory(const trajectory_msgs::JointTrajectory& message);

control_msgs::JointTrajectoryControllerState toStateMessage(const JointTrajectoryControllerState& state);

/// Serves control_msgs/QueryTrajectoryState; a refusal is logged and fails the call, as in ros_controllers.
ros::ServiceServer serveQueryState(ros::NodeHandle& handle, const std::string& name,
                                   ServiceHandler<QueryTrajectoryStateRequest> handler,
                                   const std::string& robot);

/// control_msgs/FollowJointTrajectory for ActionBridge: the ROS action and how its messages convert.
struct FollowJointTrajectoryMessages {
  using RosAction = control_msgs::FollowJointTrajectoryAction;
  using Action = FollowJointTrajectoryAction;
  static Action::Goal goal(const control_msgs::FollowJointTrajectoryGoal& message);
  static control_msgs::FollowJointTrajectoryFeedback feedback(const Action::Feedback& feedback);
  static control_msgs::FollowJointTrajectoryResult result(const Action::Result& result);
};

}  // namespace bullet_sim
