#include "bullet_sim/model/transmission.h"

#include <set>
#include <sstream>

namespace bullet_sim {

namespace {

// The children ros_control's transmission loaders know; any other is warned about once.
const std::set<std::string> kTransmissionTags = {"type", "joint", "actuator"};
const std::set<std::string> kJointTags = {"hardwareInterface", "role", "offset"};
const std::set<std::string> kActuatorTags = {"hardwareInterface", "mechanicalReduction"};

class TransmissionReader {
 public:
  TransmissionReader(const TagNode& element, Diagnostics& diagnostics)
      : element_(element), diagnostics_(diagnostics) {
    transmission_.name = element.attribute("name");
    transmission_.line = element.line;
  }

  /// The transmission, or false after a warning when ros_control would skip it.
  bool read(TransmissionSpec* out) {
    if (transmission_.name.empty()) return skip("has no name attribute");
    const TagNode* type = element_.child("type");
    if (!type || type->text.empty()) {
      return skip("has no <type> (e.g. <type>transmission_interface/SimpleTransmission</type>)");
    }
    transmission_.type = type->text;
    warnUnknown(element_, kTransmissionTags, "");
    for (const auto& child : element_.children) {
      if (child.name == "joint" && !readJoint(child)) return false;
      if (child.name == "actuator" && !readActuator(child)) return false;
    }
    if (transmission_.joints.empty()) return skip("has no <joint> with a <hardwareInterface>");
    if (transmission_.actuators.empty()) return skip("has no <actuator>");
    *out = std::move(transmission_);
    return true;
  }

 private:
  bool skip(const std::string& why) {
    diagnostics_.warning(transmission_.where() + " " + why + ": ros_control skips it");
    return false;
  }

  bool readJoint(const TagNode& element) {
    if (!element.attributes.count("name")) return skip("has a <joint> without a name attribute");
    TransmissionJoint joint;
    joint.name = element.attribute("name");
    if (joint.name.empty()) {
      diagnostics_.warning(transmission_.where() + " <joint name=\"\">: a joint needs a name; skipped");
      return true;
    }
    for (const auto& child : element.children) {
      if (child.name == "hardwareInterface" && !child.text.empty())
        joint.hardware_interfaces.push_back(child.text);
    }
    warnUnknown(element, kJointTags, "<joint name=\"" + joint.name + "\"> ");
    if (joint.hardware_interfaces.empty()) {
      diagnostics_.warning(transmission_.where() + " joint [" + joint.name +
                           "] has no <hardwareInterface>, which ros_control reads inside <joint> (no longer "
                           "inside <actuator>): the joint is skipped");
      return true;
    }
    transmission_.joints.push_back(std::move(joint));
    return true;
  }

  bool readActuator(const TagNode& element) {
    if (!element.attributes.count("name")) return skip("has an <actuator> without a name attribute");
    TransmissionActuator actuator;
    actuator.name = element.attribute("name");
    if (const TagNode* reduction = element.child("mechanicalReduction")) {
      std::istringstream in(reduction->text);
      if (!(in >> actuator.mechanical_reduction) || actuator.mechanical_reduction == 0) {
        diagnostics_.warning(transmission_.where() + " actuator [" + actuator.name +
                             "] <mechanicalReduction> must be a non-zero number, not [" + reduction->text +
                             "]: 1 is used");
        actuator.mechanical_reduction = 1;
      }
    }
    warnUnknown(element, kActuatorTags, "<actuator name=\"" + actuator.name + "\"> ");
    if (actuator.name.empty()) {
      diagnostics_.warning(transmission_.where() +
                           " <actuator name=\"\">: an actuator needs a name; skipped");
      return true;
    }
    transmission_.actuators.push_back(std::move(actuator));
    return true;
  }

  void warnUnknown(const TagNode& element, const std::set<std::string>& known, const std::string& inside) {
    std::set<std::string> warned;
    for (const auto& child : element.children) {
      if (known.count(child.name) || !warned.insert(child.name).second) continue;
      diagnostics_.warning(transmission_.where() + " " + inside + "<" + child.name +
                           "> is not a tag ros_control's transmissions know: ignored");
    }
  }

  const TagNode& element_;
  Diagnostics& diagnostics_;
  TransmissionSpec transmission_;
};

}  // namespace

std::string TransmissionSpec::where() const {
  return "transmission [" + name + "] (line " + std::to_string(line) + ")";
}

std::vector<TransmissionSpec> readTransmissions(const std::vector<TagNode>& elements,
                                                Diagnostics& diagnostics) {
  std::vector<TransmissionSpec> transmissions;
  for (const auto& element : elements) {
    TransmissionSpec transmission;
    if (TransmissionReader(element, diagnostics).read(&transmission)) transmissions.push_back(transmission);
  }
  return transmissions;
}

}  // namespace bullet_sim
