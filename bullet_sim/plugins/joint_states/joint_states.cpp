#include "plugins/joint_states/joint_states.h"

#include "bullet_sim/plugins/registry.h"

namespace bullet_sim {

namespace {

const TagTable kJointStatesTags = {
    {"robotNamespace", TagType::kText, "", "",
     "the namespace of joint_states; the model's name when absent or empty",
     "the root namespace when absent or empty; spawn_model's -robot_namespace replaces it"},
    {"jointName", TagType::kList, "every moving joint", "",
     "the joints published, separated by commas; none when absent",
     "separated by commas or spaces; every moving joint when absent; a name that is no moving joint is an "
     "error naming the nearest one"},
    {"updateRate", TagType::kRate, "100", "Hz", "how often it publishes; 0: every step", ""},
    {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
};

}  // namespace

void parseJointStates(const DeclarationSource& source, JointStatesConfig& config) {
  PluginTags& tags = source.tags;
  const ModelSpec& model = source.model;
  std::vector<std::string> names = tags.list("jointName");
  if (!tags.has("jointName")) {
    for (const auto& joint : model.joints) {
      if (joint.moves()) names.push_back(joint.name);
    }
  }
  for (const auto& name : names) {
    const JointSpec* joint = model.joint(name);
    if (!joint || !joint->moves()) {
      source.diagnostics.error(tags.where() + " <jointName> [" + name + "] is not a moving joint" +
                               didYouMean(name, model.jointNames()));
      continue;
    }
    config.joints.push_back(name);
  }
}

JointStates::JointStates(const PluginDeclaration& declaration, const JointStatesConfig& config,
                         const PluginSetup& setup)
    : Plugin(declaration, setup) {
  JointStateSample& states = states_.next();
  for (const auto& name : config.joints) {
    joints_.push_back(setup.body.jointIndex(name));
    states.names.push_back(name);
  }
  states.positions.resize(joints_.size());
  states.velocities.resize(joints_.size());
  states.efforts.resize(joints_.size());
  addOutput("joint_states", states_);
}

void JointStates::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer().due(time)) return;
  JointStateSample& states = states_.next();
  states.stamp = time.sim_time;
  for (size_t i = 0; i < joints_.size(); ++i) {
    states.positions[i] = body.jointPosition(joints_[i]);
    states.velocities[i] = body.jointVelocity(joints_[i]);
    states.efforts[i] = body.jointEffort(joints_[i]);
  }
  states_.publish();
}

BULLET_SIM_PLUGIN_FOLDER(joint_states) {
  PluginType type =
      pluginType<JointStates>("libgazebo_ros_joint_state_publisher.so", parseJointStates, kJointStatesTags);
  type.rate = {RateRule::From::kTags, {"updateRate"}, 100};
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
