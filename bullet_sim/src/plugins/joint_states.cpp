#include "bullet_sim/plugins/joint_states.h"

namespace bullet_sim {

namespace {

double readRate(const PluginSpec& spec, Diagnostics& diagnostics) {
  PluginTags tags(spec.element, "plugin [" + spec.name + "]", diagnostics);
  return tags.positive("updateRate", 100, /*allow_zero=*/true);
}

}  // namespace

JointStates::JointStates(const PluginSpec& spec, const ModelSpec& model, const RobotBody& body,
                         Diagnostics& diagnostics)
    : Plugin(spec.name), timer_(readRate(spec, diagnostics)) {
  PluginTags tags(spec.element, "plugin [" + spec.name + "]", diagnostics);
  tags.accept({"updateRate", "alwaysOn"});
  robot_namespace_ = tags.text("robotNamespace", "");
  std::vector<std::string> names = tags.list("jointName");
  if (!tags.has("jointName")) {
    for (const auto& joint : model.joints) {
      if (joint.moves()) names.push_back(joint.name);
    }
  }
  for (const auto& name : names) {
    const int index = body.jointIndex(name);
    if (index < 0) {
      diagnostics.error(tags.where() + " <jointName> [" + name + "] is not a moving joint" +
                        didYouMean(name, model.jointNames()));
      continue;
    }
    joints_.push_back(index);
    states_.names.push_back(name);
  }
  tags.finish();
  states_.positions.resize(joints_.size());
  states_.velocities.resize(joints_.size());
  states_.efforts.resize(joints_.size());
}

void JointStates::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer_.due(time)) return;
  states_.stamp = time.sim_time;
  for (size_t i = 0; i < joints_.size(); ++i) {
    states_.positions[i] = body.jointPosition(joints_[i]);
    states_.velocities[i] = body.jointVelocity(joints_[i]);
    states_.efforts[i] = body.jointEffort(joints_[i]);
  }
  ++states_count_;
}

}  // namespace bullet_sim
