#include "plugins/ros_control/pid_joint_controllers.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bullet_sim {

namespace {

/// The gains under the controller's pid/, which must give p.
PidGains requiredGains(const ControllerSetup& setup) {
  const auto gains = Pid::gainsFrom(setup.parameters.at("pid"));
  if (!gains)
    throw std::invalid_argument("pid/p is not set: give the PID gains p, i, d and i_clamp under pid/");
  return *gains;
}

}  // namespace

PidJointController::PidJointController(const ControllerSetup& setup, Target target)
    : Controller(setup, interfaceName(JointInterface::kEffort)), target_(target), pid_(requiredGains(setup)) {
  warnUnread(setup, {"joint", "pid"});
  const std::string joint = setup.parameters.text("joint", "");
  if (joint.empty()) throw std::invalid_argument("joint is not set: give the joint to control");
  joint_ = &claim(joint, JointInterface::kEffort);
  ownPorts().addInput<Float64Command>(topic("command"), [this](const Float64Command& command, double) {
    set_point_ = command.data;
    return std::string();
  });
  ownPorts().addOutput(topic("state"), state_);
}

double PidJointController::limited(double position) const {
  const JointSpec& spec = *joint_->spec;
  if (spec.type != JointSpec::Type::kRevolute && spec.type != JointSpec::Type::kPrismatic) return position;
  return std::clamp(position, spec.lower, std::max(spec.lower, spec.upper));
}

double PidJointController::error() const {
  if (target_ == Target::kVelocity) return set_point_ - joint_->velocity;
  const double target = limited(set_point_);
  if (joint_->spec->type == JointSpec::Type::kContinuous)
    return std::remainder(target - joint_->position, 2 * M_PI);  // the shortest way round
  return target - joint_->position;
}

void PidJointController::starting(double) {
  set_point_ = target_ == Target::kPosition ? limited(joint_->position) : 0.0;
  pid_.reset();
}

void PidJointController::onUpdate(double time, double period) {
  const double e = error();
  const double effort = pid_.compute(e, period);
  joint_->command = effort;
  if (updates_++ % 10 == 0) publishState(time, period, e, effort);
}

void PidJointController::publishState(double time, double period, double error, double effort) {
  JointControllerState& state = state_.next();
  state.stamp = time;
  const bool position = target_ == Target::kPosition;
  state.set_point = position ? limited(set_point_) : set_point_;
  state.process_value = position ? joint_->position : joint_->velocity;
  state.process_value_dot = position ? joint_->velocity : 0.0;
  state.error = error;
  state.time_step = period;
  state.command = effort;
  const PidGains& gains = pid_.gains();
  state.p = gains.p;
  state.i = gains.i;
  state.d = gains.d;
  state.i_clamp = gains.i_max;
  state.antiwindup = gains.antiwindup;
  state_.publish();
}

}  // namespace bullet_sim
