// Makes one joint follow another: multiplier * the leader's position + offset, as strong as maxEffort.
// Declared as the roboticsgroup mimic joint plugins Gazebo users add (Gazebo ignores URDF's <mimic>). The
// coupling is the model's (JointSpec::mimic, which URDF's <mimic> also sets): the physics holds it, so the
// plugin does nothing while the world runs. Its tags are kMimicJointTags in mimic_joint.cpp.
#pragma once

#include <string>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct MimicJointConfig : PluginConfig {
  std::string follower;  ///< a moving joint, checked ("" after an error)
  JointSpec::Mimic mimic;
};

void parseMimicJoint(const DeclarationSource& source, MimicJointConfig& config);

class MimicJoint : public Plugin {
 public:
  MimicJoint(const PluginDeclaration& declaration, const MimicJointConfig&, const PluginSetup& setup)
      : Plugin(declaration, setup) {}
};

}  // namespace bullet_sim
