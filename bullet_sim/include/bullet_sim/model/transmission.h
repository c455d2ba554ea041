// A URDF <transmission>: which hardware interface ros_control drives a joint through. Read as ros_control's
// transmission parser reads it (transmission_interface, Noetic): a transmission needs a name, a <type>, a
// named <actuator> and a named <joint> with a <hardwareInterface>. One that lacks them is skipped with a
// warning, as ros_control skips it; Gazebo loads the file all the same.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/model/plugin_tags.h"

namespace bullet_sim {

struct TransmissionJoint {
  std::string name;
  /// As written: "hardware_interface/VelocityJointInterface" or the older "VelocityJointInterface".
  std::vector<std::string> hardware_interfaces;
};

struct TransmissionActuator {
  std::string name;
  /// Read for the record: Gazebo's ros_control commands joints directly, so it scales nothing there either.
  double mechanical_reduction = 1;
};

struct TransmissionSpec {
  std::string name;
  std::string type;  ///< e.g. transmission_interface/SimpleTransmission
  std::vector<TransmissionJoint> joints;
  std::vector<TransmissionActuator> actuators;
  int line = 0;  ///< of the <transmission> element, for messages

  /// "transmission [name] (line N)": the head of every message about it.
  std::string where() const;
};

/// Reads a URDF's <transmission> elements. Every problem is a warning that names the transmission and says
/// what is skipped.
std::vector<TransmissionSpec> readTransmissions(const std::vector<TagNode>& elements,
                                                Diagnostics& diagnostics);

}  // namespace bullet_sim
