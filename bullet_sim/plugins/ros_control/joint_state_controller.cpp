#include "plugins/ros_control/joint_state_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bullet_sim/common/diagnostics.h"

namespace bullet_sim {

JointStateController::JointStateController(const ControllerSetup& setup)
    : Controller(setup, "hardware_interface::JointStateInterface") {
  const ParameterTree& parameters = setup.parameters;
  warnUnread(setup, {"publish_rate", "joints", "extra_joints"});
  if (!parameters.has("publish_rate")) {
    throw std::invalid_argument("publish_rate is not set: give the rate [Hz] to publish joint_states at");
  }
  publish_rate_ = parameters.number("publish_rate", 0);
  if (!(publish_rate_ >= 0 && std::isfinite(publish_rate_))) {  // NaN would never publish, and say nothing
    throw std::invalid_argument("publish_rate must be finite and >= 0 [Hz], not " +
                                parameters.describe("publish_rate"));
  }
  std::vector<std::string> names = parameters.texts("joints");
  if (names.empty()) {
    for (const auto& joint : hardware().joints()) names.push_back(joint.name);
    std::sort(names.begin(), names.end());
  }
  JointStateSample& sample = states_.next();
  for (const auto& name : names) {
    const HardwareJoint* joint = hardware().find(name);
    if (!joint) {
      std::vector<std::string> known;
      for (const auto& driven : hardware().joints()) known.push_back(driven.name);
      throw std::invalid_argument("joints names [" + name +
                                  "], which has no transmission ros_control drives" +
                                  didYouMean(name, known));
    }
    joints_.push_back(joint);
    sample.names.push_back(name);
  }
  sample.positions.assign(names.size(), 0.0);
  sample.velocities.assign(names.size(), 0.0);
  sample.efforts.assign(names.size(), 0.0);
  addExtraJoints(setup);
  ownPorts().addOutput("joint_states", states_);
}

void JointStateController::addExtraJoints(const ControllerSetup& setup) {
  JointStateSample& sample = states_.next();
  for (const auto& extra : setup.parameters.items("extra_joints")) {
    const std::string name = extra.text("name", "");
    const auto ignored = [&](const std::string& why) {
      setup.warnings.push_back("controller [" + this->name() + "]: extra joint " + why + ": ignored");
    };
    if (name.empty()) {
      ignored("without a name");
    } else if (std::count(sample.names.begin(), sample.names.end(), name)) {
      ignored("[" + name + "] is published already");
    } else {
      sample.names.push_back(name);
      sample.positions.push_back(extra.number("position", 0));
      sample.velocities.push_back(extra.number("velocity", 0));
      sample.efforts.push_back(extra.number("effort", 0));
    }
  }
}

void JointStateController::starting(double time) {
  if (publish_time_set_) return;
  last_publish_ = publish_rate_ > 0 ? time - 1.001 / publish_rate_ : time;  // publishes at the first update
  publish_time_set_ = true;
}

void JointStateController::onUpdate(double time, double) {
  if (!(publish_rate_ > 0) || !(last_publish_ + 1 / publish_rate_ < time)) return;
  last_publish_ += 1 / publish_rate_;
  JointStateSample& sample = states_.next();
  sample.stamp = time;
  for (size_t i = 0; i < joints_.size(); ++i) {
    sample.positions[i] = joints_[i]->position;
    sample.velocities[i] = joints_[i]->velocity;
    sample.efforts[i] = joints_[i]->effort;
  }
  states_.publish();
}

}  // namespace bullet_sim
