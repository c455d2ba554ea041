// Holds named joints at commanded positions with a motor, so that a pan/tilt does not sag under gravity.
// Declared as libgazebo_ros_joint_pose_trajectory.so (Gazebo's plugin that sets joints from a
// trajectory_msgs/JointTrajectory). Tags: topicName [set_joint_trajectory], updateRate, robotNamespace;
// ours: jointName [comma-separated; the joints held, where the robot spawned until commanded]. The motor's
// effort is the joint's URDF effort limit.
#pragma once

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

class JointPosition : public Plugin {
 public:
  JointPosition(const PluginSpec& spec, const ModelSpec& model, const RobotBody& body,
                Diagnostics& diagnostics);

  /// Commands `joint` to `position` [rad or m], clamped to its limits. False for a joint this plugin does not
  /// hold or a position that is not finite.
  bool setTarget(const std::string& joint, double position);

  void applyCommands(const StepTime& time, RobotBody& body) override;
  void reset() override;

  const std::string& topic() const { return topic_; }
  const std::string& robotNamespace() const { return robot_namespace_; }

 private:
  struct Held {
    std::string name;
    int joint;
    double lower, upper;  ///< [rad] or [m]
    double effort;        ///< [N m] or [N]
    double initial;  ///< where the robot spawned with it
    double target;
  };
  std::vector<Held> held_;
  std::string topic_ = "set_joint_trajectory";
  std::string robot_namespace_;
};

}  // namespace bullet_sim
