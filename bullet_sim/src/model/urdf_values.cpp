#include "model/urdf_values.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_sim/common/names.h"

namespace bullet_sim {

namespace {

/// What a number must be, beyond finite.
enum class Kind {
  kAny,      ///< finite (angles, limits, multipliers)
  kLength,   ///< finite, |x| <= max_length [m]
  kSize,     ///< > 0 and <= max_length [m]
  kScale,    ///< non-zero, |x| <= max_length
  kMass,     ///< |x| <= max_mass [kg] (its sign is inertiaProblem's to judge)
  kInertia,  ///< |x| <= max_inertia [kg m^2]
};

class ValueChecker {
 public:
  ValueChecker(const Limits& limits, Diagnostics& diagnostics) : limits_(limits), diagnostics_(diagnostics) {}

  /// Checks attribute `name` of `element`, when present: `count` numbers (0: any number of them).
  void check(const tinyxml2::XMLElement* element, const char* name, Kind kind, size_t count,
             const std::string& where) {
    const char* text = element ? element->Attribute(name) : nullptr;
    if (!text) return;
    const std::string at = where + " <" + element->Name() + " " + name + "=\"" + text + "\">: ";
    std::istringstream tokens(text);
    std::vector<std::string> words;
    for (std::string word; tokens >> word;) words.push_back(word);
    if (count > 0 && words.size() != count) {
      fail(at + "must be " + std::to_string(count) + (count == 1 ? " number" : " numbers"));
      return;
    }
    for (const std::string& word : words) {
      if (auto problem = numberProblem(word, kind)) {
        fail(at + *problem);
        return;  // one message per attribute
      }
    }
  }

  /// <origin xyz rpy> of `parent`.
  void origin(const tinyxml2::XMLElement* parent, const std::string& where) {
    const tinyxml2::XMLElement* origin = parent ? parent->FirstChildElement("origin") : nullptr;
    check(origin, "xyz", Kind::kLength, 3, where);
    check(origin, "rpy", Kind::kAny, 3, where);
  }

  /// The shape of a <collision> or <visual>.
  void geometry(const tinyxml2::XMLElement* shape_parent, const std::string& where) {
    const tinyxml2::XMLElement* geometry = shape_parent->FirstChildElement("geometry");
    if (!geometry) return;
    check(geometry->FirstChildElement("box"), "size", Kind::kSize, 3, where);
    check(geometry->FirstChildElement("cylinder"), "radius", Kind::kSize, 1, where);
    check(geometry->FirstChildElement("cylinder"), "length", Kind::kSize, 1, where);
    check(geometry->FirstChildElement("sphere"), "radius", Kind::kSize, 1, where);
    check(geometry->FirstChildElement("mesh"), "scale", Kind::kScale, 3, where);
  }

  /// How many numbers were refused so far.
  size_t failures() const { return failures_; }

 private:
  std::optional<std::string> numberProblem(const std::string& word, Kind kind) const {
    // urdfdom reads numbers as C++ streams do in the classic locale: decimal only, no hex, nan or inf. Of
    // those characters strtod reads exactly that, [+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?, when it reads them
    // all (std::regex took a million instructions a wheelchair, an eighth of its parse).
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(word.c_str(), &end);
    if (word.find_first_not_of("0123456789+-.eE") != std::string::npos || end != word.c_str() + word.size() ||
        word.empty()) {
      return "[" + word + "] is not a number";
    }
    if (!std::isfinite(value) || errno == ERANGE) {
      if (std::abs(value) < 1) return std::nullopt;  // underflow to (nearly) zero is harmless
      return "[" + word + "] is not a finite number";
    }
    switch (kind) {
      case Kind::kAny:
        return std::nullopt;
      case Kind::kLength:
        return boundProblem(value, limits_.max_length, "max_length", "m");
      case Kind::kSize:
        if (!(value > 0)) return "[" + word + "] must be positive";
        return boundProblem(value, limits_.max_length, "max_length", "m");
      case Kind::kScale:
        if (value == 0) return "[" + word + "] must not be zero";
        return boundProblem(value, limits_.max_length, "max_length", "");
      case Kind::kMass:
        return boundProblem(value, limits_.max_mass, "max_mass", "kg");
      case Kind::kInertia:
        return boundProblem(value, limits_.max_inertia, "max_inertia", "kg m^2");
    }
    return std::nullopt;
  }

  void fail(const std::string& message) {
    diagnostics_.error(message);
    ++failures_;
  }

  const Limits& limits_;
  Diagnostics& diagnostics_;
  size_t failures_ = 0;
};

void checkLink(const tinyxml2::XMLElement& link, ValueChecker& values) {
  const std::string where =
      "link [" + std::string(link.Attribute("name") ? link.Attribute("name") : "") + "]";
  if (const tinyxml2::XMLElement* inertial = link.FirstChildElement("inertial")) {
    const std::string here = where + " <inertial>";
    values.origin(inertial, here);
    values.check(inertial->FirstChildElement("mass"), "value", Kind::kMass, 1, here);
    for (const char* moment : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"})
      values.check(inertial->FirstChildElement("inertia"), moment, Kind::kInertia, 1, here);
  }
  for (const char* kind : {"collision", "visual"}) {
    for (auto* shape = link.FirstChildElement(kind); shape; shape = shape->NextSiblingElement(kind)) {
      const std::string here = where + " <" + kind + ">";
      values.origin(shape, here);
      values.geometry(shape, here);
    }
  }
}

void checkJoint(const tinyxml2::XMLElement& joint, ValueChecker& values) {
  const std::string where =
      "joint [" + std::string(joint.Attribute("name") ? joint.Attribute("name") : "") + "]";
  values.origin(&joint, where);
  values.check(joint.FirstChildElement("axis"), "xyz", Kind::kAny, 3, where);
  const tinyxml2::XMLElement* limit = joint.FirstChildElement("limit");
  for (const char* bound : {"lower", "upper"}) values.check(limit, bound, Kind::kAny, 1, where);
  // Negative: as warnNegativeValues says.
  values.check(limit, "effort", Kind::kAny, 1, where);
  values.check(limit, "velocity", Kind::kAny, 1, where);
  const tinyxml2::XMLElement* dynamics = joint.FirstChildElement("dynamics");
  for (const char* term : {"damping", "friction"}) values.check(dynamics, term, Kind::kAny, 1, where);
  const tinyxml2::XMLElement* mimic = joint.FirstChildElement("mimic");
  for (const char* term : {"multiplier", "offset"}) values.check(mimic, term, Kind::kAny, 1, where);
}

/// An error when `count` of `what` is above `limit`; false then.
bool withinCount(size_t count, const char* limit_name, const std::string& what, const Limits& limits,
                 Diagnostics& diagnostics) {
  const double limit = limits.get(limit_name).value_or(0);
  if (static_cast<double>(count) <= limit) return true;
  diagnostics.error("the robot has " + std::to_string(count) + " " + what + ", above the limit of " +
                    std::to_string(static_cast<size_t>(limit)) + " (" + limit_name +
                    "): is it generated by mistake? Raise the limit if it is meant");
  return false;
}

/// An error naming `what` of joint `joint` unless `value` is a number >= 0, and finite unless `unlimited` may
/// be infinite (SDF's effort and velocity limits are, when none is given).
void checkNonNegative(double value, const char* what, const JointSpec& joint, bool unlimited,
                      Diagnostics& diagnostics) {
  if (value >= 0 && (unlimited || std::isfinite(value))) return;
  std::ostringstream message;
  message << "joint [" << joint.name << "] " << what << " [" << value << "] must be a "
          << (unlimited ? "number" : "finite number") << " >= 0";
  diagnostics.error(message.str());
}

/// A joint value that Gazebo takes when negative, and what it then is.
struct NegativeReading {
  const char* element;
  const char* term;
  const char* reading;
};

constexpr NegativeReading kNegativeReadings[] = {
    // The URDF reaches Gazebo's SDF as is, where a negative limit is not enforced.
    {"limit", "effort",
     "read as no effort limit, as Gazebo reads it (SDF enforces no negative effort limit)"},
    {"limit", "velocity",
     "read as no velocity limit, as Gazebo reads it (SDF enforces no negative velocity limit)"},
    // Gazebo applies it, and the joint speeds up by itself.
    {"dynamics", "damping", "read as 0: a negative damping would speed the joint up by itself"},
    // Gazebo's ODE makes joint friction a motor's force limit, and drives no motor whose limit is not > 0.
    {"dynamics", "friction", "read as 0, as Gazebo's ODE reads it (no friction)"},
};

/// Per value of kNegativeReadings, one warning naming the joints where it is negative.
void warnNegativeValues(const tinyxml2::XMLElement& robot, Diagnostics& diagnostics) {
  std::vector<std::string> joints[std::size(kNegativeReadings)];
  for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
    const std::string name =
        "[" + std::string(joint->Attribute("name") ? joint->Attribute("name") : "") + "]";
    for (size_t k = 0; k < std::size(kNegativeReadings); ++k) {
      const tinyxml2::XMLElement* element = joint->FirstChildElement(kNegativeReadings[k].element);
      const char* term = kNegativeReadings[k].term;
      if (element && element->Attribute(term) && element->DoubleAttribute(term, 0) < 0)
        joints[k].push_back(name);
    }
  }
  for (size_t k = 0; k < std::size(kNegativeReadings); ++k) {
    if (joints[k].empty()) continue;
    const bool one = joints[k].size() == 1;
    diagnostics.warning(std::string(one ? "joint " : "joints ") + joinedNames(joints[k]) + " <" +
                        kNegativeReadings[k].element + " " + kNegativeReadings[k].term + "> " +
                        (one ? "is" : "are") + " negative: " + kNegativeReadings[k].reading);
  }
}

}  // namespace

void checkModelValues(const ModelSpec& model, const Limits& limits, Diagnostics& diagnostics) {
  size_t moving_joints = 0, shapes = 0;
  for (const JointSpec& joint : model.joints) moving_joints += joint.moves();
  for (const LinkSpec& link : model.links) shapes += link.collisions.size() + link.visuals.size();
  withinCount(model.links.size(), "max_links", "links", limits, diagnostics);
  withinCount(moving_joints, "max_moving_joints", "moving joints", limits, diagnostics);
  withinCount(shapes, "max_shapes", "collisions and visuals", limits, diagnostics);
  for (const LinkSpec& link : model.links) {
    if (!link.inertial) continue;
    const std::string where = "link [" + link.name + "] <inertial> ";
    if (auto problem = boundProblem(link.inertial->mass, limits.max_mass, "max_mass", "kg"))
      diagnostics.error(where + "mass " + *problem);
    for (int k = 0; k < 9; ++k) {
      const double moment = link.inertial->inertia.data()[k];
      if (auto problem = boundProblem(moment, limits.max_inertia, "max_inertia", "kg m^2")) {
        diagnostics.error(where + "inertia " + *problem);
        break;
      }
    }
  }
  for (const JointSpec& joint : model.joints) {
    if (std::isnan(joint.lower) || std::isnan(joint.upper))
      diagnostics.error("joint [" + joint.name + "] <limit> lower or upper is not a number");
    checkNonNegative(joint.effort, "effort", joint, true, diagnostics);
    checkNonNegative(joint.velocity, "velocity", joint, true, diagnostics);
    checkNonNegative(joint.damping, "damping", joint, false, diagnostics);
    checkNonNegative(joint.friction, "friction", joint, false, diagnostics);
  }
}

namespace {
struct ModelCounts {
  size_t links = 0, moving_joints = 0, shapes = 0;
};

/// Counts the links, moving joints and shapes of the <model>s at or under `element`, through <sdf>, <world>
/// and nested <model>s only (a plugin's own XML may have a <link> of its own).
void countModels(const tinyxml2::XMLElement& element, ModelCounts& counts) {
  for (auto* child = element.FirstChildElement(); child; child = child->NextSiblingElement()) {
    const std::string name = child->Name();
    if (name == "model" || name == "world") countModels(*child, counts);
    if (std::string(element.Name()) != "model") continue;
    if (name == "link") {
      ++counts.links;
      for (auto* shape = child->FirstChildElement(); shape; shape = shape->NextSiblingElement()) {
        const std::string kind = shape->Name();
        counts.shapes += kind == "collision" || kind == "visual";
      }
    } else if (name == "joint") {
      const char* type = child->Attribute("type");
      counts.moving_joints += !type || std::string(type) != "fixed";
    }
  }
}
}  // namespace

bool checkSdfCounts(const std::string& sdf_text, const Limits& limits, Diagnostics& diagnostics) {
  tinyxml2::XMLDocument document;
  if (document.Parse(sdf_text.c_str(), sdf_text.size()) != tinyxml2::XML_SUCCESS) return true;
  ModelCounts counts;
  if (const tinyxml2::XMLElement* root = document.RootElement()) countModels(*root, counts);
  bool fine = withinCount(counts.links, "max_links", "links", limits, diagnostics);
  fine &= withinCount(counts.moving_joints, "max_moving_joints", "moving joints", limits, diagnostics);
  fine &= withinCount(counts.shapes, "max_shapes", "collisions and visuals", limits, diagnostics);
  return fine;
}

UrdfValues checkUrdfValues(const tinyxml2::XMLElement& robot, const Limits& limits, Diagnostics& diagnostics,
                           std::set<std::string>* bad_links) {
  size_t links = 0, moving_joints = 0, shapes = 0;
  for (auto* link = robot.FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
    ++links;
    for (const char* kind : {"collision", "visual"}) {
      for (auto* shape = link->FirstChildElement(kind); shape; shape = shape->NextSiblingElement(kind))
        ++shapes;
    }
  }
  for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
    const char* type = joint->Attribute("type");
    moving_joints += !type || std::string(type) != "fixed";
  }
  bool fine = withinCount(links, "max_links", "links", limits, diagnostics);
  fine &= withinCount(moving_joints, "max_moving_joints", "moving joints", limits, diagnostics);
  fine &= withinCount(shapes, "max_shapes", "collisions and visuals", limits, diagnostics);
  if (!fine) return UrdfValues::kTooMany;  // too many to look at each

  ValueChecker values(limits, diagnostics);
  for (auto* link = robot.FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
    const size_t failures = values.failures();
    checkLink(*link, values);
    if (bad_links && values.failures() > failures && link->Attribute("name"))
      bad_links->insert(link->Attribute("name"));
  }
  for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint"))
    checkJoint(*joint, values);
  warnNegativeValues(robot, diagnostics);
  return values.failures() > 0 ? UrdfValues::kRefused : UrdfValues::kFine;
}

}  // namespace bullet_sim
