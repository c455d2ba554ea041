#include "plugins/ros_control/robot_hardware.h"

#include <algorithm>
#include <cmath>

namespace bullet_sim {

std::string interfaceName(JointInterface interface) {
  switch (interface) {
    case JointInterface::kEffort:
      return "hardware_interface::EffortJointInterface";
    case JointInterface::kVelocity:
      return "hardware_interface::VelocityJointInterface";
    case JointInterface::kPosition:
      return "hardware_interface::PositionJointInterface";
  }
  return "";
}

RobotHardware::RobotHardware(const std::vector<DrivenJoint>& joints, const RobotBody& body,
                             const ParameterTree& robot_parameters, std::vector<std::string>* warnings) {
  for (const auto& driven : joints) {
    HardwareJoint joint;
    joint.name = driven.name;
    joint.interface = driven.interface;
    joint.spec = body.spec().joint(driven.name);
    Drive drive;
    drive.index = body.jointIndex(driven.name);
    const bool urdf_limits = JointLimits::fromUrdf(*joint.spec, &drive.limits);
    const bool parameter_limits =
        JointLimits::fromParameters(robot_parameters.at("joint_limits/" + driven.name), &drive.limits);
    if (urdf_limits || parameter_limits) drive.saturation.emplace(driven.interface, drive.limits);
    const ParameterTree gains = robot_parameters.at("gazebo_ros_control/pid_gains/" + driven.name);
    if (driven.interface != JointInterface::kEffort) {
      if (const auto pid = Pid::gainsFrom(gains)) {
        drive.pid.emplace(*pid);
      } else if (!gains.keys().empty() && warnings) {
        warnings->push_back("gazebo_ros_control/pid_gains/" + driven.name +
                            " has no p gain: the joint is driven without a PID loop, as in Gazebo");
      }
    }
    joints_.push_back(joint);
    drives_.push_back(std::move(drive));
  }
  reset();
}

HardwareJoint* RobotHardware::find(const std::string& name) {
  for (auto& joint : joints_) {
    if (joint.name == name) return &joint;
  }
  return nullptr;
}

std::vector<std::string> RobotHardware::namesOf(JointInterface interface) const {
  std::vector<std::string> names;
  for (const auto& joint : joints_) {
    if (joint.interface == interface) names.push_back(joint.name);
  }
  return names;
}

void RobotHardware::read(const RobotBody& body) {
  for (size_t j = 0; j < joints_.size(); ++j) {
    const int index = drives_[j].index;
    joints_[j].position = body.jointPosition(index);
    joints_[j].velocity = body.jointVelocity(index);
    joints_[j].effort = body.jointEffort(index);
  }
}

void RobotHardware::write(RobotBody& body, double dt, bool e_stop) {
  // position joints stay where they are until a controller moves them (Gazebo snaps them to 0)
  if (!primed_) {
    for (size_t j = 0; j < joints_.size(); ++j) {
      if (joints_[j].interface == JointInterface::kPosition)
        joints_[j].command = body.jointPosition(drives_[j].index);
    }
    primed_ = true;
  }
  const bool e_stop_begins = e_stop && !e_stopped_;
  e_stopped_ = e_stop;
  for (size_t j = 0; j < joints_.size(); ++j) {
    HardwareJoint& joint = joints_[j];
    Drive& drive = drives_[j];
    if (e_stop_begins) drive.hold = joint.position;
    if (e_stop && joint.interface == JointInterface::kPosition) joint.command = drive.hold;
    if (drive.saturation)
      joint.command = drive.saturation->clip(joint.command, joint.position, joint.velocity, dt);
    if (drive.pid) {
      body.setJointEffort(drive.index, pidEffort(joint, drive, dt, e_stop));
      continue;
    }
    switch (joint.interface) {
      case JointInterface::kEffort:
        body.setJointEffort(drive.index, e_stop ? 0.0 : joint.command);
        break;
      case JointInterface::kVelocity:
        body.setJointVelocity(drive.index, e_stop ? 0.0 : joint.command, drive.limits.effortBound());
        break;
      case JointInterface::kPosition:
        body.setJointPosition(drive.index, joint.command, drive.limits.effortBound());
        break;
    }
  }
}

double RobotHardware::pidEffort(const HardwareJoint& joint, Drive& drive, double dt, bool e_stop) {
  double error = 0;
  if (joint.interface == JointInterface::kVelocity) {
    error = (e_stop ? 0.0 : joint.command) - joint.velocity;
  } else if (joint.spec->type == JointSpec::Type::kContinuous) {
    error = std::remainder(joint.command - joint.position, 2 * M_PI);  // the shortest way round
  } else {
    error = joint.command - joint.position;
  }
  const double bound = drive.limits.effortBound();
  return std::clamp(drive.pid->compute(error, dt), -bound, bound);
}

void RobotHardware::reset() {
  for (size_t j = 0; j < joints_.size(); ++j) {
    joints_[j].command = 0;
    if (drives_[j].saturation) drives_[j].saturation->reset();
    if (drives_[j].pid) drives_[j].pid->reset();
  }
  e_stopped_ = false;
  primed_ = false;
}

}  // namespace bullet_sim
