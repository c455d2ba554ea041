// urdf_doctor's check of a diff drive or skid steer: its wheels roll forward, and its motors can move.
#include "plugins/wheeled_drive/wheeled_drive.h"

#include "bullet_sim/model/model_geometry.h"

namespace bullet_sim {

namespace {

/// Every drive wheel must turn about the robot's +y (REP 103: a positive wheel speed rolls it forward).
/// Gazebo's drives send the same sign to both sides, so one reversed wheel spins the robot in place.
std::vector<PluginFinding> backwardWheels(const PluginCheckInput& input, const DriveConfig& config) {
  const auto poses = linkPosesAtZero(input.model);
  const std::string& plugin = input.declaration.name;
  std::vector<const JointSpec*> forward, backward;
  for (const auto& side : {config.left_joints, config.right_joints}) {
    for (const auto& name : side) {
      const JointSpec* joint = input.model.joint(name);
      if (!joint || !joint->moves()) continue;  // readModel reported it
      (wheelRollSign(poses, config.robot_base_frame, *joint) > 0 ? forward : backward).push_back(joint);
    }
  }
  std::vector<PluginFinding> found;
  for (const JointSpec* joint : backward) {
    const std::string against =
        forward.empty() ? "like every drive wheel of plugin [" + plugin +
                              "], so a forward command drives the robot backwards"
                        : "while joint [" + forward.front()->name + "] turns about " +
                              checks::vectorText(forward.front()->axis) + ": plugin [" + plugin +
                              "] then turns them against each other and the robot spins in place instead "
                              "of driving (bullet_sim compensates and says so, Gazebo does not)";
    const std::string subject = "joint [" + joint->name + "]";
    found.push_back({true, subject,
                     checks::message(subject,
                                     "turns about " + checks::vectorText(joint->axis) +
                                         ", backwards (-y) in [" + config.robot_base_frame + "], " + against,
                                     "write <axis xyz=\"" + checks::vectorText(-joint->axis) + "\"/>")});
  }
  return found;
}

}  // namespace

std::vector<PluginFinding> checkWheeledDrive(const PluginCheckInput& input) {
  const DriveConfig& config = *input.declaration.configAs<DriveConfig>();
  std::vector<PluginFinding> found = backwardWheels(input, config);
  for (PluginFinding& finding : checks::zeroLimitsOnMotors(input, driveWheels(config)))
    found.push_back(std::move(finding));
  return found;
}

}  // namespace bullet_sim
