#include "plugins/joint_position/joint_position.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace bullet_sim {

namespace {

const TagTable kJointPositionTags = {
    {"topicName", TagType::kTopic, "set_joint_trajectory", "",
     "the trajectory_msgs/JointTrajectory whose points it plays, setting the joints' positions",
     "the first point's positions become the targets the motors hold"},
    {"jointName", TagType::kList, "", "", "not read (bullet_sim's tag)",
     "the joints held, separated by commas or spaces, each where the robot spawned until commanded; each "
     "must move and have an effort limit, the motor's strength; without the tag, a warning, and none is "
     "held"},
    {"updateRate", TagType::kIgnored, "0", "Hz", "how often the trajectory advances; 0: every step",
     "the joints are held every step"},
    {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
};

}  // namespace

void parseJointPosition(const DeclarationSource& source, JointPositionConfig& config) {
  PluginTags& tags = source.tags;
  config.topic = tags.text("topicName");
  for (const auto& name : tags.list("jointName")) {
    const JointSpec* joint = source.model.joint(name);
    if (!joint || !joint->moves()) {
      source.diagnostics.error(tags.where() + " <jointName> [" + name + "] is not a moving joint" +
                               didYouMean(name, source.model.jointNames()));
      continue;
    }
    if (joint->effort <= 0) {
      source.diagnostics.error(
          tags.where() + " joint [" + name +
          "] has no effort limit, so nothing can hold it: set <limit effort=...> in the URDF");
    }
    config.joints.push_back(name);
  }
  if (!tags.has("jointName")) {
    source.diagnostics.warning(tags.where() + " has no <jointName> (a bullet_sim tag): it holds no joint");
  }
}

JointPosition::JointPosition(const PluginDeclaration& declaration, const JointPositionConfig& config,
                             const PluginSetup& setup)
    : Plugin(declaration, setup) {
  for (const auto& name : config.joints) {
    const JointSpec& joint = *setup.body.spec().joint(name);
    const int index = setup.body.jointIndex(name);
    const double initial = std::clamp(setup.body.jointPosition(index), joint.lower, joint.upper);
    held_.push_back({name, index, joint.lower, joint.upper, joint.effort, initial, initial});
  }
  addInput<JointTrajectory>(config.topic,
                            [this](const JointTrajectory& trajectory, double) { return take(trajectory); });
}

bool JointPosition::setTarget(const std::string& joint, double position) {
  if (!std::isfinite(position)) return false;
  for (auto& held : held_) {
    if (held.name == joint) {
      held.target = std::clamp(position, held.lower, held.upper);
      return true;
    }
  }
  return false;
}

std::string JointPosition::take(const JointTrajectory& trajectory) {
  if (trajectory.points.empty()) return "";
  const std::vector<std::string>& names = trajectory.joint_names;
  const std::vector<double>& positions = trajectory.points.front().positions;
  std::ostringstream refused;
  for (size_t i = 0; i < names.size() && i < positions.size(); ++i) {
    if (!setTarget(names[i], positions[i])) {
      refused << (refused.tellp() > 0 ? ", " : "a target it cannot hold: ") << "joint [" << names[i]
              << "] at " << positions[i];
    }
  }
  return refused.str();
}

void JointPosition::applyCommands(const StepTime&, RobotBody& body) {
  for (const auto& held : held_) body.setJointPosition(held.joint, held.target, held.effort);
}

void JointPosition::onReset() {
  for (auto& held : held_) held.target = held.initial;
}

BULLET_SIM_PLUGIN_FOLDER(joint_position) {
  PluginType type = pluginType<JointPosition>("libgazebo_ros_joint_pose_trajectory.so", parseJointPosition,
                                              kJointPositionTags);
  type.check = [](const PluginCheckInput& input) {  // urdf_doctor's: zero limits on the joints it holds
    return checks::zeroLimitsOnMotors(input, input.declaration.configAs<JointPositionConfig>()->joints);
  };
  type.tf_prefix = TfPrefixRule::kNamespaceParam;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
