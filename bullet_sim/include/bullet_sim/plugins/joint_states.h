// libgazebo_ros_joint_state_publisher.so: positions, velocities and efforts of named joints.
// Tags: jointName [comma-separated; every moving joint when absent], updateRate [100 Hz], robotNamespace.
#pragma once

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

class JointStates : public Plugin {
 public:
  JointStates(const PluginSpec& spec, const ModelSpec& model, const RobotBody& body,
              Diagnostics& diagnostics);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;
  void reset() override { timer_.reset(); }

  const std::string& robotNamespace() const { return robot_namespace_; }
  const JointStateSample& states() const { return states_; }
  uint64_t statesCount() const { return states_count_; }

 private:
  std::vector<int> joints_;
  std::string robot_namespace_;
  UpdateTimer timer_;
  JointStateSample states_;
  uint64_t states_count_ = 0;
};

}  // namespace bullet_sim
