// Holds named joints at commanded positions with a motor, so that a pan/tilt does not sag under gravity.
// Declared as libgazebo_ros_joint_pose_trajectory.so (Gazebo's plugin that sets joints from a
// trajectory_msgs/JointTrajectory). Its tags, with our jointName (the joints held), are kJointPositionTags in
// joint_position.cpp. The motor's effort is the joint's URDF effort limit.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct JointPositionConfig : PluginConfig {
  std::string topic;
  std::vector<std::string> joints;  ///< moving joints with an effort limit, checked
};

void parseJointPosition(const DeclarationSource& source, JointPositionConfig& config);

class JointPosition : public Plugin {
 public:
  JointPosition(const PluginDeclaration& declaration, const JointPositionConfig& config,
                const PluginSetup& setup);

  /// Commands `joint` to `position` [rad or m], clamped to its limits. False for a joint this plugin does not
  /// hold or a position that is not finite.
  bool setTarget(const std::string& joint, double position);

  void applyCommands(const StepTime& time, RobotBody& body) override;

 private:
  struct Held {
    std::string name;
    int joint;
    double lower, upper;  ///< [rad] or [m]
    double effort;        ///< [N m] or [N]
    double initial;       ///< where the robot spawned with it
    double target;
  };
  void onReset() override;
  /// The input: the first point of a trajectory; "" when every joint in it is held, else why not.
  /// The first waypoint's positions become the targets.
  std::string take(const JointTrajectory& trajectory);

  std::vector<Held> held_;
};

}  // namespace bullet_sim
