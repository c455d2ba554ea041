#include "bullet_sim/model/model.h"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/names.h"
#include "bullet_sim/assets/gazebo_materials.h"
#include "bullet_sim/model/model_geometry.h"
#include "model/mimic_joints.h"
#include "model/tag_node_xml.h"
#include "model/urdf_values.h"

namespace bullet_sim {

namespace {

// urdfdom reports why it rejects a file only through console_bridge; this captures it for the error message.
class CapturedConsole : public console_bridge::OutputHandler {
 public:
  CapturedConsole() { console_bridge::useOutputHandler(this); }
  ~CapturedConsole() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) messages_.push_back(text);
  }
  std::string text() const { return joined(messages_, "; "); }

 private:
  std::vector<std::string> messages_;
};

// Gazebo tags we read per link; the others that Gazebo knows are read and ignored with a warning.
const std::set<std::string> kIgnoredLinkTags = {
    "maxVel",        "minDepth",  "fdir1",  "dampingFactor", "maxContacts", "laserRetro",
    "velocityDecay", "collision", "visual", "kinematic",     "static",      "enableWireframe"};
const std::set<std::string> kIgnoredJointTags = {"provideFeedback", "implicitSpringDamper", "cfmDamping",
                                                 "stopCfm",         "stopErp",              "springStiffness",
                                                 "springReference", "fudgeFactor"};

/// Line and column of the first U+00A0 (a non-breaking space copied from a web page), if any.
std::optional<std::pair<int, int>> findNonBreakingSpace(const std::string& text) {
  int line = 1, column = 1;
  for (size_t i = 0; i + 1 < text.size(); ++i) {
    if (static_cast<unsigned char>(text[i]) == 0xC2 && static_cast<unsigned char>(text[i + 1]) == 0xA0) {
      return std::make_pair(line, column);
    }
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
      ++column;
    }
  }
  return std::nullopt;
}

std::optional<double> parseDouble(const char* text) {
  if (!text) return std::nullopt;
  std::istringstream in(text);
  double value;
  if (in >> value) return value;
  return std::nullopt;
}

std::optional<bool> parseBool(const char* text) {
  if (!text) return std::nullopt;
  const std::string value(text);
  if (value == "true" || value == "1") return true;
  if (value == "false" || value == "0") return false;
  return std::nullopt;
}

Eigen::Isometry3d parsePose(const char* text, bool* ok) {
  std::istringstream in(text ? text : "");
  double x, y, z, roll, pitch, yaw;
  *ok = static_cast<bool>(in >> x >> y >> z >> roll >> pitch >> yaw);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (!*ok) return pose;
  pose.translate(Eigen::Vector3d(x, y, z));
  pose.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
              Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
              Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
  return pose;
}

class ModelParser {
 public:
  ModelParser(Diagnostics& diagnostics, const PackageResolver& resolver, const PluginParsers& plugins,
              const Limits& limits)
      : diagnostics_(diagnostics), resolver_(resolver), plugins_(plugins), limits_(limits) {}

  /// The model as far as it can be read, every problem in `diagnostics_`; nullopt when there is no model to
  /// read (malformed XML, another root element, bad numbers or counts, urdfdom's rejection, not a tree).
  std::optional<ModelSpec> parse(const std::string& xml) {
    if (xml.size() > limits_.max_description_bytes) {
      diagnostics_.error("the description is " + std::to_string(xml.size()) + " bytes, above the limit of " +
                         std::to_string(limits_.max_description_bytes) + " (max_description_bytes)");
      return std::nullopt;
    }
    auto document = std::make_shared<tinyxml2::XMLDocument>();
    if (document->Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
      std::string message = "line " + std::to_string(document->ErrorLineNum()) + ": " + document->ErrorStr();
      if (document->ErrorID() == tinyxml2::XML_ERROR_MISMATCHED_ELEMENT) {
        message +=
            " (the element opened on that line is closed by a different tag: look for a typo or a missing "
            "closing tag below it)";
      }
      if (const auto nbsp = findNonBreakingSpace(xml)) {
        message += "; line " + std::to_string(nbsp->first) + " column " + std::to_string(nbsp->second) +
                   " holds a non-breaking space (U+00A0, often copied from a web page): replace it with a "
                   "plain space";
      }
      diagnostics_.error(message);
      return std::nullopt;
    }
    const tinyxml2::XMLElement* robot = document->RootElement();
    if (!robot || std::string(robot->Name()) != "robot") {
      diagnostics_.error("the root element is <" + std::string(robot ? robot->Name() : "") +
                         ">, not <robot>: is this a URDF?");
      return std::nullopt;
    }
    reportXacroLeftovers(robot);  // urdfdom skips such elements, so its own complaints still come out
    // urdfdom would turn some of the numbers into others, or take counts that exhaust the machine. After a
    // refused number the rest is still read, so that the file's other problems come out with it.
    const UrdfValues values = checkUrdfValues(*robot, limits_, diagnostics_, &bad_value_links_);
    if (values == UrdfValues::kTooMany) return std::nullopt;

    urdf::ModelInterfaceSharedPtr urdf_model;
    {
      CapturedConsole console;
      urdf_model = urdf::parseURDF(xml);
      // When it rejects a number already refused, its complaint adds nothing.
      if (!urdf_model && values == UrdfValues::kFine)
        diagnostics_.error("urdfdom rejected the model: " + console.text());
    }
    if (!urdf_model || !isTree(*urdf_model)) return std::nullopt;

    ModelSpec spec;
    spec.name = urdf_model->getName();
    spec.source = diagnostics_.source();
    spec.root = urdf_model->getRoot()->name;
    addTree(*urdf_model, *urdf_model->getRoot(), spec);
    readGazeboExtensions(robot, spec);
    spec.transmissions = readTransmissions(childrenNamed(*robot, "transmission"), diagnostics_);
    repairBodyInertias(spec, diagnostics_, bad_value_links_);
    reportUnmodelledTags();
    reportUnusedTransmissions(spec);
    std::vector<PluginElement> found = std::move(model_plugins_);  // model plugins first, then sensors'
    found.insert(found.end(), sensor_plugins_.begin(), sensor_plugins_.end());
    declarePlugins(found, plugins_, spec, diagnostics_, limits_);
    return spec;
  }

 private:
  /// Elements left by xacro. An element URDF does not have is skipped by urdfdom and Gazebo alike, so it is
  /// forgiven (Diagnostics::forgiven), once per name; it is usually a macro called without the xacro: prefix,
  /// which Melodic's xacro expanded and Noetic's leaves as it is.
  void reportXacroLeftovers(const tinyxml2::XMLElement* robot) {
    static const std::set<std::string> kUrdfElements = {"link", "joint", "material", "gazebo",
                                                        "transmission"};
    std::map<std::string, std::vector<int>> unknown;  // name -> its lines
    std::vector<std::string> order;
    for (auto* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string name = e->Name();
      if (name.rfind("xacro:", 0) == 0) {
        diagnostics_.error("line " + std::to_string(e->GetLineNum()) + ": <" + name +
                           "> is a xacro element: expand the file with xacro first");
      } else if (!kUrdfElements.count(name)) {
        if (unknown[name].empty()) order.push_back(name);
        unknown[name].push_back(e->GetLineNum());
      }
    }
    for (const std::string& name : order) {
      std::vector<std::string> lines;
      for (int line : unknown[name]) lines.push_back(std::to_string(line));
      diagnostics_.forgiven((lines.size() == 1 ? "line " : "lines ") + joinedNames(lines) + ": <" + name +
                            "/> is not a URDF element: ignored, as urdfdom and Gazebo ignore it (an error "
                            "in urdf_doctor and under ~strict_models); if it is a xacro macro call, write "
                            "<xacro:" + name + "/>, which Noetic's xacro expands");
    }
  }

  /// urdfdom takes a link that is the child of two joints, or links that only reach each other, and hands
  /// back a "tree" that loops for ever. Each link must be the child of one joint, and reached from the root.
  bool isTree(const urdf::ModelInterface& model) {
    std::map<std::string, std::vector<std::string>> parent_joints;  // child link -> its joints
    std::map<std::string, std::vector<std::string>> child_links;    // parent link -> its children
    for (const auto& [name, joint] : model.joints_) {
      parent_joints[joint->child_link_name].push_back(name);
      child_links[joint->parent_link_name].push_back(joint->child_link_name);
    }
    bool tree = true;
    for (const auto& [link, joints] : parent_joints) {
      if (joints.size() < 2) continue;
      diagnostics_.error("link [" + link + "] is the child of " + std::to_string(joints.size()) +
                         " joints, " + listed(joints) +
                         ": a URDF is a tree, where each link has one parent joint, so these "
                         "joints close a loop; remove all but one");
      tree = false;
    }
    if (!tree) return false;
    std::set<std::string> reached{model.getRoot()->name};
    for (std::vector<std::string> todo{model.getRoot()->name}; !todo.empty();) {
      const std::string link = todo.back();
      todo.pop_back();
      for (const auto& child : child_links[link]) {
        if (reached.insert(child).second) todo.push_back(child);
      }
    }
    std::vector<std::string> cut_off, loop_joints;
    for (const auto& [name, link] : model.links_) {
      if (reached.count(name)) continue;
      cut_off.push_back(name);
      loop_joints.insert(loop_joints.end(), parent_joints[name].begin(), parent_joints[name].end());
    }
    if (cut_off.empty()) return true;
    diagnostics_.error("links " + listed(cut_off) + " are not connected to the root link [" +
                       model.getRoot()->name + "]: their joints " + listed(loop_joints) +
                       " form a loop; a URDF is a tree, so attach them below the root");
    return false;
  }

  static std::string listed(const std::vector<std::string>& names) {
    std::string text;
    for (size_t i = 0; i < names.size(); ++i)
      text += (i == 0 ? "[" : i + 1 == names.size() ? " and [" : ", [") + names[i] + "]";
    return text;
  }

  void addTree(const urdf::ModelInterface& model, const urdf::Link& link, ModelSpec& spec) {
    spec.links.push_back(makeLink(link));
    for (const auto& joint : link.child_joints) {
      spec.joints.push_back(makeJoint(*joint));
      if (const auto child = model.getLink(joint->child_link_name)) addTree(model, *child, spec);
    }
  }

  LinkSpec makeLink(const urdf::Link& link) {
    LinkSpec spec;
    spec.name = link.name;
    if (link.inertial) {
      const urdf::Inertial& in = *link.inertial;
      InertialSpec inertial;
      inertial.mass = in.mass;
      const Eigen::Isometry3d frame = toIsometry(in.origin);
      inertial.com = frame.translation();
      Eigen::Matrix3d tensor;
      tensor << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      inertial.inertia = frame.linear() * tensor * frame.linear().transpose();
      spec.inertial = inertial;
    }
    for (const auto& collision : link.collision_array) {
      if (auto shape = makeShape(*collision->geometry, "link [" + link.name + "] <collision>", false)) {
        spec.collisions.push_back({toIsometry(collision->origin), *shape, collision->name});
      }
    }
    for (const auto& visual : link.visual_array) {
      if (auto shape = makeShape(*visual->geometry, "link [" + link.name + "] <visual>", true)) {
        Visual v;
        v.origin = toIsometry(visual->origin);
        v.shape = *shape;
        if (visual->material) {
          const auto& c = visual->material->color;
          v.rgba = Eigen::Vector4d(c.r, c.g, c.b, c.a);
          v.paint = MeshPaint::kTint;
          if (!visual->material->texture_filename.empty()) {
            diagnostics_.warning("link [" + link.name + "] <visual> <material> <texture> [" +
                                 visual->material->texture_filename +
                                 "] is not drawn (Gazebo draws no URDF textures either): the visual shows "
                                 "the material's colour");
          }
        }
        spec.visuals.push_back(v);
      }
    }
    return spec;
  }

  JointSpec makeJoint(const urdf::Joint& joint) {
    JointSpec spec;
    spec.name = joint.name;
    spec.parent = joint.parent_link_name;
    spec.child = joint.child_link_name;
    spec.origin = toIsometry(joint.parent_to_joint_origin_transform);
    spec.axis = Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z);
    static const std::map<int, JointSpec::Type> kTypes = {
        {urdf::Joint::FIXED, JointSpec::Type::kFixed},
        {urdf::Joint::REVOLUTE, JointSpec::Type::kRevolute},
        {urdf::Joint::CONTINUOUS, JointSpec::Type::kContinuous},
        {urdf::Joint::PRISMATIC, JointSpec::Type::kPrismatic}};
    if (const auto type = kTypes.find(joint.type); type != kTypes.end()) {
      spec.type = type->second;
    } else {
      diagnostics_.error(
          "joint [" + joint.name +
          "]: floating and planar joints are not supported; use fixed, revolute, continuous or "
          "prismatic");
    }
    if (spec.moves()) normalizeAxis(joint.name, spec.axis);
    if (joint.limits) {
      if (spec.type != JointSpec::Type::kContinuous) {
        spec.lower = joint.limits->lower;
        spec.upper = joint.limits->upper;
      }
      // Negative: no limit, as in Gazebo (checkUrdfValues warns); NaN stays, for checkModelValues to refuse.
      spec.effort = joint.limits->effort < 0 ? 0.0 : joint.limits->effort;
      spec.velocity = joint.limits->velocity < 0 ? 0.0 : joint.limits->velocity;
      if (spec.effort > limits_.max_effort) {
        std::ostringstream message;
        message << "joint [" << joint.name << "] <limit effort=\"" << spec.effort << "\">: " << spec.effort
                << " is above the limit of " << limits_.max_effort << " (max_effort): " << limits_.max_effort
                << " is used";
        diagnostics_.warning(message.str());
        spec.effort = limits_.max_effort;
      }
    }
    if (joint.dynamics) {  // negative: 0 (checkUrdfValues warns)
      spec.damping = joint.dynamics->damping < 0 ? 0.0 : joint.dynamics->damping;
      spec.friction = joint.dynamics->friction < 0 ? 0.0 : joint.dynamics->friction;
    }
    if (joint.mimic) {
      spec.mimic = JointSpec::Mimic{joint.mimic->joint_name, joint.mimic->multiplier, joint.mimic->offset, 0,
                                    "<mimic>"};
    }
    return spec;
  }

  /// The shape; nullopt after an error, or after a warning for a `visual` whose mesh cannot be found (Gazebo
  /// loads such a robot: that visual is not drawn).
  std::optional<Shape> makeShape(const urdf::Geometry& geometry, const std::string& where, bool visual) {
    Shape shape;
    switch (geometry.type) {
      case urdf::Geometry::BOX: {
        const auto& dim = static_cast<const urdf::Box&>(geometry).dim;
        shape.type = Shape::Type::kBox;
        shape.box_size = Eigen::Vector3d(dim.x, dim.y, dim.z);
        return shape;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
        shape.type = Shape::Type::kCylinder;
        shape.radius = cylinder.radius;
        shape.length = cylinder.length;
        return shape;
      }
      case urdf::Geometry::SPHERE:
        shape.type = Shape::Type::kSphere;
        shape.radius = static_cast<const urdf::Sphere&>(geometry).radius;
        return shape;
      case urdf::Geometry::MESH: {
        const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
        shape.type = Shape::Type::kMesh;
        shape.mesh_scale = Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z);
        std::string error;
        const auto path = resolver_.resolve(mesh.filename, &error);
        std::error_code ec;
        if (visual && path && !std::filesystem::exists(*path, ec)) error = "cannot find mesh [" + *path + "]";
        if (visual && (!path || !std::filesystem::exists(*path, ec))) {
          diagnostics_.warning(where + ": " + error + ": that visual is not drawn");
          return std::nullopt;
        }
        if (!path) {
          diagnostics_.error(where + ": " + error);
          return std::nullopt;
        }
        shape.mesh_path = *path;
        std::vector<std::string> warnings;
        shape.mesh = meshes_.load(*path, shape.mesh_scale, &error, &warnings);
        for (const std::string& warning : warnings) diagnostics_.warning(where + ": " + warning);
        if (!shape.mesh) {
          diagnostics_.error(where + ": " + error);
          return std::nullopt;
        }
        triangles_ += shape.mesh->triangles.size();
        if (triangles_ > limits_.max_triangles) {
          diagnostics_.error(where + ": mesh [" + *path + "] brings the robot's meshes to " +
                             std::to_string(triangles_) + " triangles, above the limit of " +
                             std::to_string(limits_.max_triangles) + " (max_triangles): simplify the meshes");
          return std::nullopt;
        }
        return shape;
      }
    }
    diagnostics_.error(where + ": unsupported geometry");
    return std::nullopt;
  }

  void readGazeboExtensions(const tinyxml2::XMLElement* robot, ModelSpec& spec) {
    const auto links = spec.linkNames();
    const auto joints = spec.jointNames();
    std::vector<std::string> frames = links;
    frames.insert(frames.end(), joints.begin(), joints.end());

    for (auto* gazebo = robot->FirstChildElement("gazebo"); gazebo;
         gazebo = gazebo->NextSiblingElement("gazebo")) {
      const std::string line = "line " + std::to_string(gazebo->GetLineNum()) + ": ";
      const char* reference = gazebo->Attribute("reference");
      if (!reference) {
        readModelBlock(gazebo, line, spec);
      } else if (auto link = std::find_if(spec.links.begin(), spec.links.end(),
                                          [&](const LinkSpec& l) { return l.name == reference; });
                 link != spec.links.end()) {
        readLinkBlock(gazebo, line, *link);
      } else if (auto joint = std::find_if(spec.joints.begin(), spec.joints.end(),
                                           [&](const JointSpec& j) { return j.name == reference; });
                 joint != spec.joints.end()) {
        readJointBlock(gazebo, line, *joint);
      } else {
        diagnostics_.forgiven(line + "<gazebo reference=\"" + reference + "\"> names no link or joint" +
                              didYouMean(reference, frames) +
                              ": the block is skipped, as Gazebo skips it (an error under ~strict_models)");
      }
    }
  }

  void readModelBlock(const tinyxml2::XMLElement* gazebo, const std::string& line, ModelSpec& spec) {
    for (auto* tag = gazebo->FirstChildElement(); tag; tag = tag->NextSiblingElement()) {
      if (std::string(tag->Name()) == "plugin") {
        model_plugins_.push_back({readTagNode(*tag), std::nullopt, std::nullopt, line});
      } else if (std::string(tag->Name()) == "static") {
        const auto value = parseBool(tag->GetText());
        if (!value) diagnostics_.error(line + "<gazebo> <static> must be true or false");
        spec.is_static = value.value_or(false);
      } else {
        ignoreTag(line + "<gazebo> ", tag->Name(), "", false);
      }
    }
  }

  /// Makes a moving joint's axis a unit one. Gazebo's ODE normalizes any axis (dJointSetHingeAxis), so only
  /// a zero one is an error; one shorter than sdformat 12 takes (kShortestAxis) is its direction, with a
  /// warning.
  void normalizeAxis(const std::string& joint, Eigen::Vector3d& axis) {
    const auto text = [](const Eigen::Vector3d& v) {
      std::ostringstream out;
      out << v.x() << " " << v.y() << " " << v.z();
      return out.str();
    };
    std::ostringstream message;
    message << "joint [" << joint << "] <axis xyz=\"" << text(axis) << "\">";
    if (axis.isZero(0)) {
      diagnostics_.error(message.str() + " is zero: give it a direction such as 0 1 0");
      return;
    }
    const double length = axis.stableNorm();
    axis.stableNormalize();
    if (length > kShortestAxis) return;
    message << " is " << length << " long: read as its direction, " << text(axis)
            << ", as Gazebo's ODE normalizes it";
    diagnostics_.warning(message.str());
  }

  void readLinkBlock(const tinyxml2::XMLElement* gazebo, const std::string& line, LinkSpec& link) {
    const std::string where = line + "<gazebo reference=\"" + link.name + "\"> ";
    for (auto* tag = gazebo->FirstChildElement(); tag; tag = tag->NextSiblingElement()) {
      const std::string name = tag->Name();
      // <mu1 value="1"/> reads as <mu1>1</mu1>, as sdformat reads it (Clearpath writes every wheel so).
      const char* text = tag->GetText() ? tag->GetText() : tag->Attribute("value");
      // Friction and contact figures: >= 0. A negative friction coefficient is unlimited, as in Gazebo.
      const auto number = [&](double* out, bool negative_is_unlimited = false) {
        const auto value = parseDouble(text);
        if (value && std::isfinite(*value) && *value >= 0) {
          *out = *value;
        } else if (value && *value < 0 && negative_is_unlimited) {
          diagnostics_.warning(where + "<" + name + "> [" + text + "] is negative: " +
                               SurfaceSpec::kNegativeMuReading);
          *out = SurfaceSpec::kUnlimitedMu;
        } else {
          diagnostics_.error(where + "<" + name + "> must be a number >= 0, not [" + (text ? text : "") +
                             "]");
        }
      };
      const auto flag = [&](bool* out) {
        if (auto value = parseBool(text)) {
          *out = *value;
        } else {
          diagnostics_.error(where + "<" + name + "> must be true or false");
        }
      };
      if (name == "material") {
        applyMaterial(text ? text : "", where, link);
      } else if (name == "mu1") {
        number(&link.surface.mu1, /*negative_is_unlimited=*/true);
      } else if (name == "mu2") {
        number(&link.surface.mu2, /*negative_is_unlimited=*/true);
      } else if (name == "kp") {
        double kp = 0;
        number(&kp);
        link.surface.kp = kp;
      } else if (name == "kd") {
        double kd = 0;
        number(&kd);
        link.surface.kd = kd;
      } else if (name == "selfCollide") {
        flag(&link.self_collide);
      } else if (name == "turnGravityOff") {
        bool off = false;
        flag(&off);
        link.gravity = !off;
      } else if (name == "gravity") {
        flag(&link.gravity);
      } else if (name == "sensor") {
        makeSensor(tag, link.name, where);
      } else {
        ignoreTag(where, name, link.name, kIgnoredLinkTags.count(name) > 0);
      }
    }
  }

  void readJointBlock(const tinyxml2::XMLElement* gazebo, const std::string& line, JointSpec& joint) {
    const std::string where = line + "<gazebo reference=\"" + joint.name + "\"> ";
    for (auto* tag = gazebo->FirstChildElement(); tag; tag = tag->NextSiblingElement()) {
      const std::string name = tag->Name();
      if (name == "disableFixedJointLumping" || name == "preserveFixedJoint") {
        if (const auto value = parseBool(tag->GetText())) {
          joint.lumping_disabled |= *value;
        } else {
          diagnostics_.error(where + "<" + name + "> must be true or false");
        }
      } else {
        ignoreTag(where, name, joint.name, kIgnoredJointTags.count(name) > 0);
      }
    }
  }

  /// Gazebo's table, else the material scripts on Gazebo's resource path (read once), as Gazebo finds them.
  void applyMaterial(const std::string& material, const std::string& where, LinkSpec& link) {
    std::optional<Eigen::Vector4d> colour = gazeboMaterialColour(material);
    std::string texture_warning;
    if (!colour && script_colours_.count(material)) {
      colour = script_colours_[material];
    } else if (!colour) {  // read once for all links that name it
      const std::vector<std::string>& resource_path = resolver_.gazeboPaths().resourcePath();
      if (!resource_scripts_) resource_scripts_ = resourceMaterialScripts(resource_path);
      colour = scriptMaterialColour(material, *resource_scripts_, resourceTextureFolders(resource_path),
                                    &texture_warning);
      script_colours_[material] = colour;
    }
    if (!texture_warning.empty() && unknown_materials_.insert(material).second) {
      diagnostics_.warning(where + "<material>" + material + "</material>: " + texture_warning +
                           (colour ? "; drawn in its colour" : "; the URDF colour is kept"));
    }
    if (!colour) {
      if (unknown_materials_.insert(material).second) {
        diagnostics_.warning(
            where + "<material>" + material + "</material> is neither a Gazebo material we know" +
            didYouMean(material, gazeboMaterialNames()) +
            " nor one that a material script on Gazebo's resource path defines with a colour; "
            "the URDF colour is kept");
      }
      return;
    }
    for (auto& visual : link.visuals) {
      visual.rgba = *colour;
      visual.material = material;
      visual.paint = MeshPaint::kUniform;
    }
  }

  void makeSensor(const tinyxml2::XMLElement* element, const std::string& link, const std::string& where) {
    SensorDeclaration sensor;
    sensor.link = link;
    sensor.name = element->Attribute("name") ? element->Attribute("name") : "";
    sensor.type = element->Attribute("type") ? element->Attribute("type") : "";
    const std::string here = where + "<sensor name=\"" + sensor.name + "\"> ";
    if (sensor.type.empty()) diagnostics_.error(here + "has no type attribute (e.g. type=\"ray\")");
    if (auto* pose = element->FirstChildElement("pose")) {
      bool ok = false;
      sensor.pose = parsePose(pose->GetText(), &ok);
      if (!ok) diagnostics_.error(here + "<pose> must be six numbers: x y z roll pitch yaw");
      for (int i = 0; ok && i < 3; ++i) {
        if (auto problem =
                boundProblem(sensor.pose.translation()[i], limits_.max_length, "max_length", "m")) {
          diagnostics_.error(here + "<pose> " + "xyz"[i] + " " + *problem);
          sensor.pose = Eigen::Isometry3d::Identity();
          break;
        }
      }
    }
    if (auto* rate = element->FirstChildElement("update_rate")) {
      const auto value = parseDouble(rate->GetText());
      if (!value) {
        diagnostics_.error(here + "<update_rate> must be a number [Hz], not [" +
                           (rate->GetText() ? rate->GetText() : "") + "]");
      } else {
        sensor.update_rate = sensorUpdateRate(*value, here, diagnostics_);
      }
    }
    const auto* plugin_element = element->FirstChildElement("plugin");
    if (!plugin_element) {
      diagnostics_.warning("sensor [" + sensor.name + "] on link [" + link +
                           "] has no <plugin>, so Gazebo publishes nothing from it: ignored");
      return;
    }
    sensor_plugins_.push_back(
        {readTagNode(*plugin_element), std::move(sensor), readTagNode(*element), where});
  }

  static std::vector<TagNode> childrenNamed(const tinyxml2::XMLElement& parent, const char* name) {
    std::vector<TagNode> children;
    for (auto* child = parent.FirstChildElement(name); child; child = child->NextSiblingElement(name))
      children.push_back(readTagNode(*child));
    return children;
  }

  /// A Gazebo tag bullet_sim does not model (`known`: ODE's contact and joint figures, ...) goes into the
  /// model's one line about them; an unknown one, likely a typo, gets its own warning.
  void ignoreTag(const std::string& where, const std::string& tag, const std::string& owner, bool known) {
    if (known) {
      unmodelled_[tag].push_back(owner);
    } else {
      diagnostics_.warning(where + "<" + tag + "> is not a Gazebo tag bullet_sim knows: ignored");
    }
  }

  /// One line for the model, listing each tag bullet_sim does not model and where it is.
  void reportUnmodelledTags() {
    if (unmodelled_.empty()) return;
    std::string text;
    for (const auto& [tag, owners] : unmodelled_)
      text += std::string(text.empty() ? "" : "; ") + "<" + tag + "> on " + listed(owners);
    diagnostics_.warning("Gazebo tags that bullet_sim does not model (ODE's) are ignored: " + text);
  }

  /// One line when the model has <transmission>s but no libgazebo_ros_control.so to read them.
  void reportUnusedTransmissions(const ModelSpec& spec) {
    if (spec.transmissions.empty()) return;
    for (const PluginElement& element : model_plugins_) {
      if (element.plugin.attribute("filename") == "libgazebo_ros_control.so") return;
    }
    std::vector<std::string> names;
    for (const TransmissionSpec& transmission : spec.transmissions) names.push_back(transmission.name);
    const bool one = names.size() == 1;
    diagnostics_.warning(
        std::string(one ? "<transmission> " : "<transmission>s ") + listed(names) + (one ? " is" : " are") +
        " not used: only libgazebo_ros_control.so reads transmissions, and the robot declares "
        "no <plugin> of it (Gazebo does not use them either)");
  }

  Diagnostics& diagnostics_;
  const PackageResolver& resolver_;
  const PluginParsers& plugins_;
  const Limits& limits_;
  size_t triangles_ = 0;  ///< of every mesh shape so far
  /// Links with a number checkUrdfValues refused: what urdfdom made of it is no further fault.
  std::set<std::string> bad_value_links_;
  MeshCache meshes_{limits_};
  std::set<std::string> unknown_materials_;  ///< Gazebo material names warned about, once each
  std::optional<std::vector<std::string>> resource_scripts_;              ///< see applyMaterial
  std::map<std::string, std::optional<Eigen::Vector4d>> script_colours_;  ///< by material name
  std::vector<PluginElement> model_plugins_;
  std::vector<PluginElement> sensor_plugins_;
  std::map<std::string, std::vector<std::string>> unmodelled_;  ///< see ignoreTag: tag -> links, joints
};

}  // namespace

void declarePlugins(const std::vector<PluginElement>& elements, const PluginParsers& plugins,
                    ModelSpec& model, Diagnostics& diagnostics, const Limits& limits) {
  for (const PluginElement& element : elements) {
    PluginDeclaration declaration;
    declaration.name = element.plugin.attribute("name");
    declaration.filename = element.plugin.attribute("filename");
    declaration.sensor = element.sensor;
    if (declaration.filename.empty()) {
      diagnostics.error(element.where + "<plugin name=\"" + declaration.name + "\"> has no filename");
      continue;
    }
    const std::string where = declaration.sensor ? declaration.where() + " plugin [" + declaration.name + "]"
                                                 : declaration.where();
    PluginTags tags(&element.plugin, where, diagnostics);
    const DeclarationSource source{declaration, tags, element.sensor_tags ? &*element.sensor_tags : nullptr,
                                   model, diagnostics, limits};
    declaration.config = plugins.parse(source);
    if (declaration.config) model.plugins.push_back(std::move(declaration));
  }
  plugins.completeModel(model, diagnostics);
  resolveMimics(model, limits, diagnostics);
}

const LinkSpec* ModelSpec::link(const std::string& name) const {
  for (const auto& l : links) {
    if (l.name == name) return &l;
  }
  return nullptr;
}

JointSpec* ModelSpec::joint(const std::string& name) {
  return const_cast<JointSpec*>(static_cast<const ModelSpec&>(*this).joint(name));
}

const JointSpec* ModelSpec::joint(const std::string& name) const {
  for (const auto& j : joints) {
    if (j.name == name) return &j;
  }
  return nullptr;
}

const JointSpec* ModelSpec::parentJoint(const std::string& link) const {
  for (const auto& j : joints) {
    if (j.child == link) return &j;
  }
  return nullptr;
}

std::vector<std::string> ModelSpec::linkNames() const {
  std::vector<std::string> names;
  for (const auto& l : links) names.push_back(l.name);
  return names;
}

std::vector<std::string> ModelSpec::jointNames() const {
  std::vector<std::string> names;
  for (const auto& j : joints) names.push_back(j.name);
  return names;
}

ModelSpec parseModel(const std::string& urdf_xml, const std::string& source, const PackageResolver& resolver,
                     const PluginParsers& plugins, std::vector<std::string>* warnings, const Limits& limits,
                     bool strict) {
  Diagnostics diagnostics(source, strict);
  std::optional<ModelSpec> spec = readModel(urdf_xml, resolver, plugins, diagnostics, limits);
  diagnostics.throwIfErrors();
  if (warnings)
    warnings->insert(warnings->end(), diagnostics.warnings().begin(), diagnostics.warnings().end());
  return std::move(*spec);
}

std::optional<ModelSpec> readModel(const std::string& urdf_xml, const PackageResolver& resolver,
                                   const PluginParsers& plugins, Diagnostics& diagnostics,
                                   const Limits& limits) {
  return ModelParser(diagnostics, resolver, plugins, limits).parse(urdf_xml);
}

}  // namespace bullet_sim
