// libgazebo_ros_joint_state_publisher.so: positions, velocities and efforts of named joints, on joint_states.
// Its tags are kJointStatesTags in joint_states.cpp.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct JointStatesConfig : PluginConfig {
  std::vector<std::string> joints;  ///< moving joints, checked
};

void parseJointStates(const DeclarationSource& source, JointStatesConfig& config);

class JointStates : public Plugin {
 public:
  JointStates(const PluginDeclaration& declaration, const JointStatesConfig& config,
              const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

 private:
  std::vector<int> joints_;
  Stream<JointStateSample> states_;
};

}  // namespace bullet_sim
