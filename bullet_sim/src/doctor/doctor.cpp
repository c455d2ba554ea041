#include "bullet_sim/doctor/doctor.h"

#include <tinyxml2.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

// The doctor reads the plugins with the simulator's own config parsers, so that their checks see the same
// tags and defaults that a spawn would.
#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/plugins/plugin_checks.h"
#include "bullet_sim/plugins/registry.h"
#include "model/urdf_values.h"

namespace bullet_sim {

namespace {

constexpr double kGroundTolerance = 0.002;  // [m] lowest collision vs z = 0 of the footprint
constexpr double kTwoPi = 2 * M_PI;
// Exported CAD inertia differs from that of simple collision shapes by a few times, not by ten, and a
// hundred times off is a placeholder (the seeds' 1.0 kg m^2 on 0.1 kg wheels) or a typo.
constexpr double kInertiaWarningRatio = 10;
constexpr double kInertiaErrorRatio = 100;
constexpr double kDensestMaterial = 22590;  // [kg/m^3] osmium, the densest element
constexpr double kVisualGap = 0.01;  // [m] a collision farther than this from every visual is misplaced
// Mirrored wheels: positions within this [m], plus a share of the track between them, are mirror images.
constexpr double kMirrorTolerance = 0.01;
constexpr double kMirrorShare = 0.05;
// A wheel's axis points mostly along the line between the mirrored wheels (cos 45 degrees).
constexpr double kAlongTrack = 0.7;
// A pasted file can hold hundreds of look-alike characters; the first few locate the cause.
constexpr size_t kMaxCharacterFindings = 5;

using Severity = DoctorFinding::Severity;

/// Characters that look like spaces or quotes in an editor but are not XML's.
struct LookAlike {
  const char* utf8;
  const char* name;
  const char* fix;
};
const LookAlike kLookAlikes[] = {
    {"\xC2\xA0", "a non-breaking space (U+00A0, often copied from a web page)",
     "replace it with a plain space"},
    {"\xE3\x80\x80", "an ideographic space (U+3000)", "replace it with a plain space"},
    {"\xE2\x80\x8B", "a zero-width space (U+200B)", "delete it"},
    {"\xEF\xBB\xBF", "a byte order mark (U+FEFF) inside the text", "delete it"},
    {"\xE2\x80\x9C", "a curly quote (U+201C)", "replace it with a straight quote \""},
    {"\xE2\x80\x9D", "a curly quote (U+201D)", "replace it with a straight quote \""},
};

struct CharacterAt {
  int line = 0;
  int column = 0;  ///< in characters, from 1
  const LookAlike* what = nullptr;
};

std::vector<CharacterAt> findLookAlikes(const std::string& text) {
  std::vector<CharacterAt> found;
  int line = 1, column = 1;
  for (size_t i = 0; i < text.size(); ++i) {
    for (const LookAlike& look : kLookAlikes) {
      const bool leading_bom = i == 0 && std::string(look.utf8) == "\xEF\xBB\xBF";
      if (!leading_bom && text.compare(i, std::strlen(look.utf8), look.utf8) == 0) {
        found.push_back({line, column, &look});
      }
    }
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {  // not a UTF-8 continuation byte
      ++column;
    }
  }
  return found;
}

std::string lineOf(const std::string& text, int line) {
  std::istringstream in(text);
  std::string current;
  for (int n = 1; std::getline(in, current); ++n) {
    if (n == line) return current;
  }
  return "";
}

using checks::message;
using checks::number;
using checks::vectorText;

/// A unit direction as a user writes it: components within rounding of 0 (a turn by 1.5707963) are 0.
std::string directionText(const Eigen::Vector3d& v) {
  return vectorText(v.unaryExpr([](double c) { return std::abs(c) < 1e-6 ? 0.0 : c; }));
}

/// Why tinyxml2 could not parse the text, located by line and column, with the likely cause.
std::string parseFailure(const tinyxml2::XMLDocument& document, const std::string& text,
                         const std::vector<CharacterAt>& look_alikes) {
  const int line = document.ErrorLineNum();
  for (const CharacterAt& at : look_alikes) {
    if (at.line == line) {
      return message("line " + std::to_string(at.line) + " column " + std::to_string(at.column),
                     "XML cannot be parsed (" + std::string(document.ErrorName()) + " at line " +
                         std::to_string(line) + "): this column holds " + at.what->name +
                         ", which XML does not take for a space or a quote",
                     at.what->fix);
    }
  }
  // tinyxml2 names the element it was reading ("... XMLElement name=inertial"): point at where it opens.
  const std::string error = document.ErrorStr() ? document.ErrorStr() : "";
  const auto named = error.find("name=");
  const std::string element = named == std::string::npos ? "" : error.substr(named + 5);
  const std::string source_line = lineOf(text, line);
  size_t column = element.empty() ? std::string::npos : source_line.find("<" + element);
  if (column == std::string::npos) column = source_line.find_first_not_of(" \t");
  if (column == std::string::npos) column = 0;
  const std::string where = "line " + std::to_string(line) + " column " + std::to_string(column + 1);
  const std::string tag = element.empty() ? "an element" : "<" + element + ">";
  std::string problem, fix;
  switch (document.ErrorID()) {
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
      problem = tag + " is closed by another element's closing tag, or not at all (a closing tag that lost " +
                "its '</', such as `" + element + ">`, is read as text)";
      fix = "close it with </" + element + "> before its parent closes";
      break;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
      problem = "an attribute of " + tag + " is malformed";
      fix = "write every attribute as name=\"value\", and '<' or '&' inside a value as &lt; or &amp;";
      break;
    case tinyxml2::XML_ERROR_PARSING_ELEMENT:
      problem = "a tag on this line is malformed (a stray character inside < >?)";
      fix = "write the tag as <name attribute=\"value\"/> or <name>...</name>";
      break;
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT:
      return message("the file", "holds no XML element", "give it a <robot> element");
    case tinyxml2::XML_ERROR_PARSING:
      problem =
          "XML cannot be parsed: the text ends before its elements are closed, or something follows "
          "the root element";
      fix = "close every element, and keep one <robot> root";
      break;
    default:
      problem = "XML cannot be parsed: " + error;
      fix = "correct the XML there";
  }
  if (!look_alikes.empty()) {  // not on the error line, but worth knowing about
    const CharacterAt& first = look_alikes.front();
    problem += " (line " + std::to_string(first.line) + " column " + std::to_string(first.column) +
               " also holds " + first.what->name + ")";
  }
  return message(where, problem, fix);
}

/// Inertia about its own centre, in its own frame [kg m^2], of a shape of mass `mass` [kg].
Eigen::Matrix3d shapeInertia(const Shape& shape, double mass) {
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();
  switch (shape.type) {
    case Shape::Type::kBox: {
      const Eigen::Vector3d s2 = shape.box_size.cwiseProduct(shape.box_size);
      moments = mass / 12 * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y());
      break;
    }
    case Shape::Type::kCylinder: {
      const double across = mass * (3 * shape.radius * shape.radius + shape.length * shape.length) / 12;
      moments = Eigen::Vector3d(across, across, mass * shape.radius * shape.radius / 2);
      break;
    }
    case Shape::Type::kSphere:
      moments.setConstant(0.4 * mass * shape.radius * shape.radius);
      break;
    case Shape::Type::kMesh:
    case Shape::Type::kPlane:
      break;
  }
  return moments.asDiagonal();
}

/// Volume [m^3] of a primitive; nullopt for a mesh or a plane, whose volume we do not compute.
std::optional<double> primitiveVolume(const Shape& shape) {
  switch (shape.type) {
    case Shape::Type::kBox:
      return shape.box_size.prod();
    case Shape::Type::kCylinder:
      return M_PI * shape.radius * shape.radius * shape.length;
    case Shape::Type::kSphere:
      return 4.0 / 3.0 * M_PI * std::pow(shape.radius, 3);
    case Shape::Type::kMesh:
    case Shape::Type::kPlane:
      return std::nullopt;
  }
  return std::nullopt;
}

const char* shapeName(Shape::Type type) {
  switch (type) {
    case Shape::Type::kBox:
      return "box";
    case Shape::Type::kCylinder:
      return "cylinder";
    case Shape::Type::kSphere:
      return "sphere";
    case Shape::Type::kMesh:
      return "mesh";
    case Shape::Type::kPlane:
      return "plane";
  }
  return "shape";
}

bool isPrimitive(Shape::Type type) {
  return type == Shape::Type::kBox || type == Shape::Type::kCylinder || type == Shape::Type::kSphere;
}

class Examination {
 public:
  Examination(const std::string& xml, const std::string& source, const PackageResolver& resolver,
              const Limits& limits, const PluginRegistry& registry)
      : xml_(xml), resolver_(resolver), limits_(limits), registry_(registry) {
    report_.source = source;
  }

  DoctorReport run() {
    const auto look_alikes = findLookAlikes(xml_);
    if (document_.Parse(xml_.c_str(), xml_.size()) != tinyxml2::XML_SUCCESS) {
      return unreadable(parseFailure(document_, xml_, look_alikes));
    }
    const tinyxml2::XMLElement* robot = document_.RootElement();
    if (!robot) return unreadable(message("the file", "holds no XML element", "give it a <robot> element"));
    if (std::string(robot->Name()) != "robot") {
      return unreadable(message("the root element <" + std::string(robot->Name()) + ">",
                                "this is not a URDF, whose root is <robot>",
                                "give urdf_doctor a URDF or a xacro that expands to one"));
    }
    reportLookAlikes(look_alikes);

    // what Gazebo forgives silently is an error here
    Diagnostics diagnostics(report_.source, /*strict=*/true);
    const std::optional<ModelSpec> model =
        readModel(xml_, resolver_, registry_, diagnostics, limits_);
    for (const auto& error : diagnostics.errors()) add(Severity::kError, error);
    for (const auto& warning : diagnostics.warnings()) add(Severity::kWarning, warning);

    checkFrameTags(*robot);
    if (model) examineModel(*model, *robot);
    return report_;
  }

 private:
  /// The doctor's own checks of what the loader read. Links whose shapes the loader dropped (a mesh it could
  /// not load) or whose numbers it refused are left out of the checks that their shapes or numbers would
  /// mislead: their fault is already reported.
  void examineModel(const ModelSpec& model, const tinyxml2::XMLElement& robot) {
    Diagnostics scratch(report_.source);  // the loader reported these values' problems
    std::set<std::string> refused;
    checkUrdfValues(robot, limits_, scratch, &refused);
    const std::set<std::string> lost_collisions = linksMissing(model, robot, "collision");
    const std::set<std::string> lost_visuals = linksMissing(model, robot, "visual");

    if (lost_collisions.empty()) checkFootprint(model);  // a lost wheel mesh would move the lowest point
    checkPlugins(model, zeroLimitsOf(robot));
    checkMirroredWheelAxes(model, lost_collisions);
    checkRevoluteLimits(model);
    checkLimitRanges(model);
    for (const auto& link : model.links) {
      if (refused.count(link.name) || lost_collisions.count(link.name)) continue;
      checkInertiaAgainstShapes(link);
      if (!lost_visuals.count(link.name)) checkCollisionsMeetVisuals(model, link);
    }
  }

  /// Links with fewer `kind` elements ("collision" or "visual") in the model than in the XML: the loader
  /// could not load a mesh of theirs.
  static std::set<std::string> linksMissing(const ModelSpec& model, const tinyxml2::XMLElement& robot,
                                            const char* kind) {
    std::set<std::string> missing;
    for (auto* element = robot.FirstChildElement("link"); element;
         element = element->NextSiblingElement("link")) {
      const LinkSpec* link = element->Attribute("name") ? model.link(element->Attribute("name")) : nullptr;
      if (!link) continue;
      size_t written = 0;
      for (auto* shape = element->FirstChildElement(kind); shape; shape = shape->NextSiblingElement(kind))
        ++written;
      const size_t read = std::string(kind) == "collision" ? link->collisions.size() : link->visuals.size();
      if (written != read) missing.insert(link->name);
    }
    return missing;
  }

  void add(Severity severity, const std::string& text) { report_.findings.push_back({severity, text}); }

  /// Whether a finding so far says `text`.
  bool reported(const std::string& text) const {
    return std::any_of(report_.findings.begin(), report_.findings.end(),
                       [&](const DoctorFinding& f) { return f.message.find(text) != std::string::npos; });
  }

  DoctorReport unreadable(const std::string& why) {
    report_.readable = false;
    add(Severity::kError, why);
    return report_;
  }

  /// Look-alike characters in a file that still parsed: between elements they are text nobody reads, but
  /// inside a tag or a value they break the file (urdfdom then says why too).
  void reportLookAlikes(const std::vector<CharacterAt>& found) {
    for (size_t i = 0; i < std::min(found.size(), kMaxCharacterFindings); ++i) {
      const CharacterAt& at = found[i];
      std::string problem = "holds " + std::string(at.what->name) +
                            ", which XML does not take for a space or a quote; it parsed here, but the same "
                            "character inside a tag or a value breaks the file";
      if (i + 1 == kMaxCharacterFindings && found.size() > kMaxCharacterFindings)
        problem += " (and " + std::to_string(found.size() - kMaxCharacterFindings) + " more like it)";
      add(Severity::kWarning,
          message("line " + std::to_string(at.line) + " column " + std::to_string(at.column), problem,
                  at.what->fix));
    }
  }

  /// Plugin tags that name a link: a wrong one means Gazebo publishes in a frame nobody has, or loads
  /// nothing.
  void checkFrameTags(const tinyxml2::XMLElement& robot) {
    std::vector<std::string> links;
    for (auto* link = robot.FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
      if (link->Attribute("name")) links.push_back(link->Attribute("name"));
    }
    for (auto* gazebo = robot.FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      for (auto* child = gazebo->FirstChildElement(); child; child = child->NextSiblingElement()) {
        const std::string name = child->Name();
        if (name == "plugin") checkPluginFrames(*child, {"robotBaseFrame", "bodyName"}, links);
        if (name == "sensor") {
          for (auto* plugin = child->FirstChildElement("plugin"); plugin;
               plugin = plugin->NextSiblingElement("plugin")) {
            checkPluginFrames(*plugin, {"frameName"}, links);
          }
        }
      }
    }
  }

  void checkPluginFrames(const tinyxml2::XMLElement& plugin, std::initializer_list<const char*> tags,
                         const std::vector<std::string>& links) {
    const std::string plugin_name = plugin.Attribute("name") ? plugin.Attribute("name") : "";
    for (const char* tag : tags) {
      const auto* element = plugin.FirstChildElement(tag);
      if (!element || !element->GetText()) continue;
      std::string frame = element->GetText();
      frame.erase(0, frame.find_first_not_of(" \t\n/"));  // tf2 frames carry no leading slash
      frame.erase(frame.find_last_not_of(" \t\n") + 1);
      if (std::find(links.begin(), links.end(), frame) != links.end()) continue;
      if (frame == "world" || frame == "map") continue;  // global frames (a bumper's default is world)
      if (reported("<" + std::string(tag) + "> [" + frame + "] is not a link")) continue;  // by the loader
      const std::string suggestion = closestName(frame, links);
      // A warning, as the loader's: Gazebo takes the name as the frame_id.
      add(Severity::kWarning,
          message("line " + std::to_string(element->GetLineNum()) + ": plugin [" + plugin_name + "] <" + tag +
                      ">" + frame + "</" + tag + ">",
                  "names no link, so Gazebo loads nothing or publishes in a frame no one has",
                  suggestion.empty() ? "name one of the model's links"
                                     : "did you mean [" + suggestion + "]? Write <" + tag + ">" + suggestion +
                                           "</" + tag + ">"));
    }
  }

  /// With a footprint root (REP 120: the base projected on the ground), the wheels must reach z = 0 of it at
  /// the zero pose, or Gazebo drops the robot from that height or spawns it sunk into the ground.
  void checkFootprint(const ModelSpec& model) {
    std::string root = model.root;
    std::transform(root.begin(), root.end(), root.begin(), [](unsigned char c) { return std::tolower(c); });
    if (root.find("footprint") == std::string::npos) return;
    const auto poses = linkPosesAtZero(model);
    double lowest = std::numeric_limits<double>::infinity();
    std::string lowest_link;
    for (const auto& link : model.links) {
      for (const auto& collision : link.collisions) {
        const double z = lowestPoint(collision.shape, poses.at(link.name) * collision.origin);
        if (z < lowest) {
          lowest = z;
          lowest_link = link.name;
        }
      }
    }
    if (!std::isfinite(lowest) || std::abs(lowest) <= kGroundTolerance) return;
    std::string problem = "at the zero pose the lowest collision (link [" + lowest_link + "]) is " +
                          number(std::abs(lowest)) + " m " + (lowest < 0 ? "below" : "above") + " [" +
                          model.root + "], which should be the ground: Gazebo spawns the robot " +
                          (lowest < 0 ? "sunk into the ground and it jumps up" : "in the air and it falls") +
                          " (bullet_sim lifts it onto its wheels, but then [" + model.root +
                          "] is off the ground)";
    std::vector<const JointSpec*> from_root;
    for (const auto& joint : model.joints) {
      if (joint.parent == model.root) from_root.push_back(&joint);
    }
    if (from_root.size() == 1) {
      const double z = from_root.front()->origin.translation().z();
      add(Severity::kError, message("joint [" + from_root.front()->name + "]", problem,
                                    "set its <origin> z to " + number(z - lowest) + " (now " + number(z) +
                                        ") so the wheels touch z = 0 of [" + model.root + "]"));
    } else {
      add(Severity::kError,
          message("link [" + model.root + "]", problem,
                  "move the joints below [" + model.root + "] up by " + number(-lowest) + " m"));
    }
  }

  /// Each plugin's own check, as its type registered it (readModel reported the plugins' tag problems). When
  /// two plugins find a fault in the same element, the first one's finding is reported.
  void checkPlugins(const ModelSpec& model, const std::vector<ZeroLimit>& zero_limits) {
    std::set<std::string> subjects;
    for (const auto& plugin : model.plugins) {
      const PluginType* type = registry_.typeOf(plugin);
      if (!type || !type->check) continue;
      for (const PluginFinding& finding : type->check({model, plugin, zero_limits})) {
        if (!subjects.insert(finding.subject).second) continue;
        add(finding.error ? Severity::kError : Severity::kWarning, finding.message);
      }
    }
  }

  /// The <limit>s that write effort or velocity as 0, read from the XML: the model cannot tell a
  /// <limit effort="0"> from no <limit> at all.
  static std::vector<ZeroLimit> zeroLimitsOf(const tinyxml2::XMLElement& robot) {
    std::vector<ZeroLimit> found;
    for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
      const char* name = joint->Attribute("name");
      const auto* limit = joint->FirstChildElement("limit");
      if (!name || !limit) continue;
      ZeroLimit zero{name, limit->GetLineNum(), {}};
      for (const char* attribute : {"effort", "velocity"}) {
        if (limit->Attribute(attribute) && limit->DoubleAttribute(attribute, -1) == 0)
          zero.attributes.push_back(attribute);
      }
      if (!zero.attributes.empty()) found.push_back(std::move(zero));
    }
    return found;
  }

  /// The wheel joints that drive plugins name, on either side.
  std::set<std::string> driveWheels(const ModelSpec& model) const {
    std::set<std::string> joints;
    for (const auto& plugin : model.plugins) {
      const PluginType* type = registry_.typeOf(plugin);
      if (!type || !type->driven) continue;
      const DrivenJoints driven = type->driven(plugin);
      joints.insert(driven.left_wheels.begin(), driven.left_wheels.end());
      joints.insert(driven.right_wheels.begin(), driven.right_wheels.end());
    }
    return joints;
  }

  /// A wheel as the geometry shows it: a joint that turns for ever (continuous, or revolute with a full turn
  /// of range) and carries a round or mesh collision, or one the loader dropped (a mesh it could not load).
  struct Wheel {
    const JointSpec* joint;
    Eigen::Vector3d position;  ///< of its link, in the root frame at the zero pose
    Eigen::Vector3d axis;      ///< in the root frame
  };

  /// The bounding box of a link's collisions placed at `pose`; empty without any (or with unloaded meshes).
  static Eigen::AlignedBox3d collisionBox(const LinkSpec& link, const Eigen::Isometry3d& pose) {
    Eigen::AlignedBox3d box;
    for (const auto& collision : link.collisions)
      box.extend(boundingBox(collision.shape, pose * collision.origin));
    return box;
  }

  /// The wheels of a model: links on turning joints that carry a round collision (or lost a mesh) and reach
  /// down to the robot's lowest collision (within half their height), as wheels on the ground do and arms
  /// and flippers held up do not.
  static std::vector<Wheel> wheelsOf(const ModelSpec& model, const std::set<std::string>& dropped) {
    const auto poses = linkPosesAtZero(model);
    double ground = std::numeric_limits<double>::infinity();
    for (const auto& link : model.links) {
      const Eigen::AlignedBox3d box = collisionBox(link, poses.at(link.name));
      if (!box.isEmpty()) ground = std::min(ground, box.min().z());
    }
    std::vector<Wheel> wheels;
    for (const auto& joint : model.joints) {
      const bool turns = joint.type == JointSpec::Type::kContinuous ||
                         (joint.type == JointSpec::Type::kRevolute && joint.upper - joint.lower >= kTwoPi);
      const LinkSpec* link = model.link(joint.child);
      if (!turns || !link || !poses.count(link->name)) continue;
      const Eigen::Isometry3d& pose = poses.at(link->name);
      const Eigen::AlignedBox3d box = collisionBox(*link, pose);
      const bool round =
          std::any_of(link->collisions.begin(), link->collisions.end(), [](const Collision& c) {
            return c.shape.type == Shape::Type::kCylinder || c.shape.type == Shape::Type::kSphere ||
                   c.shape.type == Shape::Type::kMesh;
          });
      const bool on_ground =
          !box.isEmpty() && box.min().z() <= ground + std::max(kMirrorTolerance, box.sizes().z() / 2);
      if (dropped.count(link->name) || (round && on_ground))
        wheels.push_back({&joint, pose.translation(), pose.linear() * joint.axis});
    }
    return wheels;
  }

  /// The wheel mirroring `wheel` across the root's x-z plane, nearest first; nullptr when none does.
  static const Wheel* mirrorOf(const Wheel& wheel, const std::vector<Wheel>& wheels) {
    const Wheel* best = nullptr;
    double best_gap = std::numeric_limits<double>::infinity();
    for (const Wheel& other : wheels) {
      const double track = std::abs(wheel.position.y() - other.position.y());
      const Eigen::Vector3d mirrored(other.position.x(), -other.position.y(), other.position.z());
      const double gap = (wheel.position - mirrored).norm();
      if (&other == &wheel || track <= kMirrorTolerance || gap > kMirrorTolerance + kMirrorShare * track)
        continue;
      if (gap < best_gap) best = &other, best_gap = gap;
    }
    return best;
  }

  /// Mirrored wheels, found from the geometry alone, must turn about the same direction across the robot:
  /// every drive (Gazebo's diff drive and skid steer, ros_control's diff_drive_controller) sends both sides
  /// the same sign to go forward. The one turning about -y (REP 103: +y rolls a wheel forward) is reported;
  /// wheels a drive plugin names are the drive's own check's.
  void checkMirroredWheelAxes(const ModelSpec& model, const std::set<std::string>& dropped) {
    const std::set<std::string> driven = driveWheels(model);
    const std::vector<Wheel> wheels = wheelsOf(model, dropped);
    for (const Wheel& wheel : wheels) {
      const Wheel* mirror = mirrorOf(wheel, wheels);
      if (!mirror || mirrorOf(*mirror, wheels) != &wheel) continue;  // pairs only, each way
      if (driven.count(wheel.joint->name) && driven.count(mirror->joint->name)) continue;
      const bool along_track =
          std::abs(wheel.axis.y()) >= kAlongTrack && std::abs(mirror->axis.y()) >= kAlongTrack;
      if (!along_track || wheel.axis.y() >= 0 || mirror->axis.y() < 0) continue;
      add(Severity::kError,
          message(
              "joint [" + wheel.joint->name + "]",
              "turns about " + directionText(wheel.axis) + " in [" + model.root + "], while joint [" +
                  mirror->joint->name + "], its mirror image across the robot, turns about " +
                  directionText(mirror->axis) +
                  ": a drive (Gazebo's diff drive and skid steer, ros_control's diff_drive_controller) "
                  "sends both sides the same sign to go forward, so these wheels turn against each other "
                  "and the robot spins in place",
              "write <axis xyz=\"" + directionText(-wheel.joint->axis) + "\"/>, so that both turn about +y"));
    }
  }

  void checkRevoluteLimits(const ModelSpec& model) {
    for (const auto& joint : model.joints) {
      if (joint.type != JointSpec::Type::kRevolute) continue;
      const double widest = std::max(std::abs(joint.lower), std::abs(joint.upper));
      if (!std::isfinite(widest) || widest <= kTwoPi) continue;
      add(Severity::kError,
          message("joint [" + joint.name + "] <limit>",
                  "lower " + number(joint.lower) + " and upper " + number(joint.upper) +
                      " go beyond a full turn: URDF limits are radians and these look like degrees",
                  "write radians (180 degrees = 3.14159), or make the joint continuous if it turns freely, "
                  "as a wheel does"));
    }
  }

  /// A revolute or prismatic joint whose range is empty or a single point cannot move: usually a wheel or a
  /// hinge written as revolute with its <limit> left at URDF's lower = upper = 0.
  void checkLimitRanges(const ModelSpec& model) {
    for (const auto& joint : model.joints) {
      if (joint.type != JointSpec::Type::kRevolute && joint.type != JointSpec::Type::kPrismatic) continue;
      if (!std::isfinite(joint.lower) || !std::isfinite(joint.upper) || joint.lower < joint.upper) continue;
      const std::string where = "joint [" + joint.name + "] <limit>";
      if (joint.lower == joint.upper) {
        add(Severity::kError,
            message(where,
                    "lower and upper are both " + number(joint.lower) +
                        ", so the joint cannot move (URDF's lower and upper are 0 when left out)",
                    joint.type == JointSpec::Type::kRevolute
                        ? "give the range it turns through, or make the joint fixed if it must not move, or "
                          "continuous if it turns freely, as a wheel does"
                        : "give the range it slides through, or make the joint fixed if it must not move"));
      } else {
        add(Severity::kError, message(where,
                                      "lower " + number(joint.lower) + " is above upper " +
                                          number(joint.upper) + ": no position lies within the limits",
                                      "swap them: lower=\"" + number(joint.upper) + "\" upper=\"" +
                                          number(joint.lower) + "\""));
      }
    }
  }

  /// The URDF inertia against that of the link's collision shapes, filled uniformly with the link's mass.
  void checkInertiaAgainstShapes(const LinkSpec& link) {
    if (!link.inertial || link.collisions.empty()) return;
    const InertialSpec& inertial = *link.inertial;
    if (inertiaProblem(inertial.mass, inertial.inertia)) return;  // readModel reported it
    double volume = 0;
    for (const auto& collision : link.collisions) {
      const auto v = primitiveVolume(collision.shape);
      if (!v) return;  // a mesh: no volume to compare with
      volume += *v;
    }
    if (!std::isfinite(volume) || volume <= 0) return;
    const std::string where = "link [" + link.name + "] <inertial>";
    const double density = inertial.mass / volume;
    if (density > kDensestMaterial) {
      add(Severity::kError,
          message(where,
                  "mass " + number(inertial.mass) + " kg in " + number(volume * 1000) +
                      " L of collision shapes is " + number(density) +
                      " kg/m^3, denser than any material (osmium: 22590 kg/m^3)",
                  "check the <mass> (a misplaced decimal point?) and the collision's size"));
    }

    // The shapes' inertia about their common centre of mass, in the link frame.
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& collision : link.collisions)
      centre += *primitiveVolume(collision.shape) / volume * collision.origin.translation();
    Eigen::Matrix3d shapes = Eigen::Matrix3d::Zero();
    for (const auto& collision : link.collisions) {
      const double mass = inertial.mass * *primitiveVolume(collision.shape) / volume;
      const Eigen::Matrix3d rotation = collision.origin.linear();
      const Eigen::Vector3d d = collision.origin.translation() - centre;
      shapes += rotation * shapeInertia(collision.shape, mass) * rotation.transpose() +
                mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
    }
    const Eigen::Vector3d expected = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(shapes).eigenvalues();
    const Eigen::Vector3d given =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertial.inertia).eigenvalues();
    if (!expected.allFinite() || expected.minCoeff() <= 0) return;
    const Eigen::Vector3d ratio = given.cwiseQuotient(expected);
    const double worst = std::max(ratio.maxCoeff(), 1 / ratio.minCoeff());
    if (worst <= kInertiaWarningRatio) return;
    add(worst > kInertiaErrorRatio ? Severity::kError : Severity::kWarning,
        message(
            where,
            "principal moments " + vectorText(given) + " kg m^2 are " + number(worst) +
                " times off those of its collision shapes at " + number(inertial.mass) + " kg (" +
                vectorText(expected) + " kg m^2): the link will " +
                (ratio.maxCoeff() > 1 ? "resist turning like a flywheel" : "spin up far too easily"),
            "compute the inertia from the mass and the shape (a cylinder about its axis: m r^2 / 2; a box "
            "across x: m (y^2 + z^2) / 12), or export it from CAD with the real mass"));
  }

  /// Collisions are in the link frame like visuals; one that sits nowhere near any visual usually repeats
  /// the joint origin (seeds 001/002), so the robot rolls on wheels that are not where they are drawn.
  void checkCollisionsMeetVisuals(const ModelSpec& model, const LinkSpec& link) {
    Eigen::AlignedBox3d visuals;
    for (const auto& visual : link.visuals) visuals.extend(boundingBox(visual.shape, visual.origin));
    if (visuals.isEmpty()) return;
    const JointSpec* joint = model.parentJoint(link.name);
    for (const auto& collision : link.collisions) {
      const Eigen::AlignedBox3d box = boundingBox(collision.shape, collision.origin);
      const double gap = box.isEmpty() ? 0 : box.exteriorDistance(visuals);
      if (!std::isfinite(gap) || gap <= kVisualGap) continue;
      const double offset = (box.center() - visuals.center()).norm();
      const Eigen::Vector3d at = collision.origin.translation();
      std::string problem = "its " + std::string(shapeName(collision.shape.type)) + " at xyz " +
                            vectorText(at) + " is " + number(offset) +
                            " m from its visual, which it does not even touch";
      if (joint && (joint->origin.translation() - at).norm() < 1e-3 && !at.isZero(1e-6))
        problem += ": its <origin> repeats the origin of joint [" + joint->name +
                   "], but the link frame is already there";
      add(Severity::kError, message("link [" + link.name + "] <collision>", problem,
                                    "give the collision the visual's <origin> (xyz " +
                                        vectorText(link.visuals.front().origin.translation()) + ")"));
    }
    if (link.collisions.size() == 1 && link.visuals.size() == 1) {
      const Shape::Type collision = link.collisions.front().shape.type;
      const Shape::Type visual = link.visuals.front().shape.type;
      if (isPrimitive(collision) && isPrimitive(visual) && collision != visual) {
        add(Severity::kWarning,
            message("link [" + link.name + "] <collision>",
                    "it is a " + std::string(shapeName(collision)) + " while its visual is a " +
                        shapeName(visual) + ": the robot bumps into a shape no one sees",
                    "use the visual's geometry for the collision"));
      }
    }
  }

  const std::string& xml_;
  const PackageResolver& resolver_;
  const Limits& limits_;
  const PluginRegistry& registry_;
  tinyxml2::XMLDocument document_;
  DoctorReport report_;
};

}  // namespace

size_t DoctorReport::errors() const {
  return std::count_if(findings.begin(), findings.end(),
                       [](const DoctorFinding& f) { return f.severity == Severity::kError; });
}

size_t DoctorReport::warnings() const { return findings.size() - errors(); }

int DoctorReport::exitCode(bool warnings_as_errors) const {
  if (!readable) return 2;
  return errors() > 0 || (warnings_as_errors && warnings() > 0) ? 1 : 0;
}

std::string DoctorReport::text() const {
  std::string text;
  for (const auto& finding : findings)
    text += source + (finding.severity == Severity::kError ? ": error: " : ": warning: ") + finding.message +
            "\n";
  if (!readable) return text + source + ": not readable, nothing else was checked\n";
  const auto plural = [](size_t n, const std::string& word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
  };
  return text + source + ": " +
         (findings.empty() ? "clean" : plural(errors(), "error") + ", " + plural(warnings(), "warning")) +
         "\n";
}

DoctorReport examineUrdf(const std::string& urdf_xml, const std::string& source,
                         const PackageResolver& resolver, const Limits& limits) {
  return examineUrdf(urdf_xml, source, resolver, limits, PluginRegistry::builtin());
}

DoctorReport examineUrdf(const std::string& urdf_xml, const std::string& source,
                         const PackageResolver& resolver, const Limits& limits,
                         const PluginRegistry& registry) {
  return Examination(urdf_xml, source, resolver, limits, registry).run();
}

DoctorReport unreadableReport(const std::string& source, const std::string& reason) {
  DoctorReport report;
  report.source = source;
  report.readable = false;
  report.findings.push_back({Severity::kError, reason});
  return report;
}

}  // namespace bullet_sim
