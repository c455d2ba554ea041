#include "bullet_sim/plugins/joint_position.h"

#include <algorithm>
#include <cmath>

namespace bullet_sim {

JointPosition::JointPosition(const PluginSpec& spec, const ModelSpec& model, const RobotBody& body,
                             Diagnostics& diagnostics)
    : Plugin(spec.name) {
  PluginTags tags(spec.element, "plugin [" + spec.name + "]", diagnostics);
  topic_ = tags.text("topicName", topic_);
  robot_namespace_ = tags.text("robotNamespace", "");
  tags.accept({"updateRate", "alwaysOn"});
  for (const auto& name : tags.list("jointName")) {
    const JointSpec* joint = model.joint(name);
    if (!joint || !joint->moves()) {
      diagnostics.error(tags.where() + " <jointName> [" + name + "] is not a moving joint" +
                        didYouMean(name, model.jointNames()));
      continue;
    }
    if (joint->effort <= 0) {
      diagnostics.error(tags.where() + " joint [" + name +
                        "] has no effort limit, so nothing can hold it: set <limit effort=...> in the URDF");
      continue;
    }
    const int index = body.jointIndex(name);
    const double initial = std::clamp(body.jointPosition(index), joint->lower, joint->upper);
    held_.push_back({name, index, joint->lower, joint->upper, joint->effort, initial, initial});
  }
  if (!tags.has("jointName")) {
    diagnostics.warning(tags.where() + " has no <jointName> (a bullet_sim tag): it holds no joint");
  }
  tags.finish();
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

void JointPosition::applyCommands(const StepTime&, RobotBody& body) {
  for (const auto& held : held_) body.setJointPosition(held.joint, held.target, held.effort);
}

void JointPosition::reset() {
  for (auto& held : held_) held.target = held.initial;
}

}  // namespace bullet_sim
