#include "plugins/mimic_joint/mimic_joint.h"

#include "bullet_sim/plugins/registry.h"

namespace bullet_sim {

namespace {

const TagTable kMimicJointTags = {
    {"joint", TagType::kText, "", "", "the joint followed (required)", ""},
    {"mimicJoint", TagType::kText, "", "", "the joint that follows (required)", ""},
    {"multiplier", TagType::kNumber, "1", "", "the follower's position per unit of the followed joint's", ""},
    {"offset", TagType::kNumber, "0", "rad or m", "added to the follower's position", ""},
    {"maxEffort", TagType::kPositive, "the follower's effort limit", "N m or N",
     "the follower's fmax (unused when it sets the position)",
     "the coupling's strength: it pushes both joints with at most this effort"},
    {"sensitiveness", TagType::kIgnored, "0", "rad or m", "the error below which the follower is left alone",
     "the coupling holds every error"},
    {"hasPID", TagType::kIgnored, "", "",
     "drives the follower with a PID whose gains are under <hasPID>'s namespace "
     "(gazebo_ros_control/pid_gains/<mimicJoint> when empty) instead of setting its position",
     "accepted with a warning: the coupling is a constraint either way, and no gains are read"},
};

}  // namespace

void parseMimicJoint(const DeclarationSource& source, MimicJointConfig& config) {
  PluginTags& tags = source.tags;
  const std::string leader = tags.text("joint", "");
  const std::string follower = tags.text("mimicJoint", "");
  config.mimic.multiplier = tags.number("multiplier");
  config.mimic.offset = tags.number("offset");
  config.mimic.max_effort = tags.has("maxEffort") ? tags.positive("maxEffort", 0) : 0;  // 0: resolveMimics
  config.mimic.joint = leader;
  config.mimic.source = source.declaration.where();
  if (tags.has("hasPID")) {
    source.diagnostics.warning(tags.where() + " <hasPID>: bullet_sim couples the joints by a constraint as "
                               "strong as maxEffort; no PID gains are read");
  }
  bool known = true;
  for (const auto& [tag, name] : {std::pair{"joint", leader}, std::pair{"mimicJoint", follower}}) {
    const JointSpec* joint = source.model.joint(name);
    if (joint && joint->moves()) continue;
    source.diagnostics.warning(tags.where() + " <" + tag + "> [" + name + "] is not a moving joint" +
                               didYouMean(name, source.model.jointNames()) +
                               ": the plugin couples nothing (Gazebo's does not load)");
    known = false;
  }
  if (known) config.follower = follower;
}

BULLET_SIM_PLUGIN_FOLDER(mimic_joint) {
  for (const char* filename :
       {"libroboticsgroup_upatras_gazebo_mimic_joint_plugin.so",
        "libroboticsgroup_gazebo_mimic_joint_plugin.so", "libgazebo_mimic_joint_plugin.so"}) {
    PluginType type = pluginType<MimicJoint>(filename, parseMimicJoint, kMimicJointTags);
    type.mimic =
        [](const PluginDeclaration& declaration) -> std::optional<std::pair<std::string, JointSpec::Mimic>> {
      const auto* config = declaration.configAs<MimicJointConfig>();
      if (config->follower.empty()) return std::nullopt;
      return std::pair{config->follower, config->mimic};
    };
    registrar.add(std::move(type));
  }
}

}  // namespace bullet_sim
