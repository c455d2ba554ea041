#include "trajectory_messages.h"

#include <control_msgs/QueryTrajectoryState.h>

namespace bullet_sim {

namespace {

TrajectoryPoint toPoint(const trajectory_msgs::JointTrajectoryPoint& message) {
  return {message.positions, message.velocities, message.accelerations, message.effort,
          message.time_from_start.toSec()};
}

trajectory_msgs::JointTrajectoryPoint toPointMessage(const TrajectoryPoint& point) {
  trajectory_msgs::JointTrajectoryPoint message;
  message.positions = point.positions;
  message.velocities = point.velocities;
  message.accelerations = point.accelerations;
  message.effort = point.effort;
  message.time_from_start = ros::Duration(point.time_from_start);
  return message;
}

std::vector<JointTolerance> toTolerances(const std::vector<control_msgs::JointTolerance>& messages) {
  std::vector<JointTolerance> tolerances;
  for (const auto& message : messages)
    tolerances.push_back({message.name, message.position, message.velocity, message.acceleration});
  return tolerances;
}

}  // namespace

JointTrajectory toTrajectory(const trajectory_msgs::JointTrajectory& message) {
  JointTrajectory trajectory;
  trajectory.stamp = message.header.stamp.toSec();
  trajectory.joint_names = message.joint_names;
  for (const auto& point : message.points) trajectory.points.push_back(toPoint(point));
  return trajectory;
}

control_msgs::JointTrajectoryControllerState toStateMessage(const JointTrajectoryControllerState& state) {
  control_msgs::JointTrajectoryControllerState message;
  message.header.stamp = ros::Time(state.stamp);
  message.joint_names = state.joint_names;
  message.desired = toPointMessage(state.desired);
  message.actual = toPointMessage(state.actual);
  message.error = toPointMessage(state.error);
  return message;
}

ros::ServiceServer serveQueryState(ros::NodeHandle& handle, const std::string& name,
                                   ServiceHandler<QueryTrajectoryStateRequest> handler,
                                   const std::string& robot) {
  using Service = control_msgs::QueryTrajectoryState;
  return handle.advertiseService<Service::Request, Service::Response>(
      name, [handler, robot](Service::Request& request, Service::Response& response) {
        QueryTrajectoryStateRequest::Reply reply;
        const std::string refused = handler({request.time.toSec()}, reply);
        if (!refused.empty()) {
          ROS_ERROR("[%s] %s", robot.c_str(), refused.c_str());
          return false;
        }
        response.name = reply.name;
        response.position = reply.position;
        response.velocity = reply.velocity;
        response.acceleration = reply.acceleration;
        return true;
      });
}

FollowJointTrajectoryAction::Goal FollowJointTrajectoryMessages::goal(
    const control_msgs::FollowJointTrajectoryGoal& message) {
  Action::Goal goal;
  goal.trajectory = toTrajectory(message.trajectory);
  goal.path_tolerance = toTolerances(message.path_tolerance);
  goal.goal_tolerance = toTolerances(message.goal_tolerance);
  goal.goal_time_tolerance = message.goal_time_tolerance.toSec();
  return goal;
}

control_msgs::FollowJointTrajectoryFeedback FollowJointTrajectoryMessages::feedback(
    const Action::Feedback& feedback) {
  const control_msgs::JointTrajectoryControllerState state = toStateMessage(feedback);
  control_msgs::FollowJointTrajectoryFeedback message;
  message.header = state.header;
  message.joint_names = state.joint_names;
  message.desired = state.desired;
  message.actual = state.actual;
  message.error = state.error;
  return message;
}

control_msgs::FollowJointTrajectoryResult FollowJointTrajectoryMessages::result(
    const Action::Result& result) {
  control_msgs::FollowJointTrajectoryResult message;
  message.error_code = result.error_code;
  message.error_string = result.error_string;
  return message;
}

}  // namespace bullet_sim
