#include "bullet_sim/model/world.h"

#include <tinyxml2.h>
#include <sdf/sdf.hh>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <type_traits>

#include "bullet_sim/common/files.h"
#include "bullet_sim/common/names.h"
#include "bullet_sim/assets/gazebo_materials.h"
#include "bullet_sim/assets/mesh.h"
#include "bullet_sim/model/sdf_model.h"
#include "model/tag_node_xml.h"
#include "model/world_copies.h"
#include "model/sdf9_values.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

constexpr double kPlaneVisualThickness = 0.001;  // [m] of the box that stands in for a plane visual

/// A number as SDF would write it: "0.1", not "0.100000".
std::string toText(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

std::string toText(const Eigen::Vector3d& v) {
  return toText(v.x()) + " " + toText(v.y()) + " " + toText(v.z());
}

bool hasScheme(const std::string& uri, const std::string& scheme) {
  return uri.rfind(scheme + "://", 0) == 0;
}

/// A path from a package://, model://, file:// or relative URI, relative ones taken from `base_directory`.
/// On failure returns nullopt and sets `error` to the reason and the fix.
/// Whether `uri` is a package://, model:// or file:// URI, or a path.
bool supportedScheme(const std::string& uri) {
  return uri.find("://") == std::string::npos || hasScheme(uri, "package") || hasScheme(uri, "file") ||
         hasScheme(uri, "model");
}

std::optional<fs::path> resolveFile(const std::string& uri, const PackageResolver& resolver,
                                    const fs::path& base_directory, std::string* error) {
  if (!supportedScheme(uri)) {
    *error = "unsupported URI scheme in [" + uri +
             "]; use package://, model://, file:// or a path relative to the SDF file";
    return std::nullopt;
  }
  const std::optional<std::string> resolved = resolver.resolve(uri, error);
  if (!resolved) return std::nullopt;
  const fs::path path = fs::path(*resolved).is_relative() ? base_directory / *resolved : fs::path(*resolved);
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    *error = "no such file [" + path.string() + "]; check the path";
    return std::nullopt;
  }
  return path;
}

Eigen::Vector3d toEigen(const ignition::math::Vector3d& v) { return {v.X(), v.Y(), v.Z()}; }

Eigen::Isometry3d toIsometry(const ignition::math::Pose3d& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = toEigen(pose.Pos());
  result.linear() = Eigen::Quaterniond(pose.Rot().W(), pose.Rot().X(), pose.Rot().Y(), pose.Rot().Z())
                        .normalized()
                        .toRotationMatrix();
  return result;
}

Eigen::Vector4d toRgba(const ignition::math::Color& colour) {
  return {colour.R(), colour.G(), colour.B(), colour.A()};
}

/// "[file:line] " for messages. SDF text has no file, so sdformat's placeholder name becomes `source`.
std::string location(const std::string& file, const std::optional<int>& line, const std::string& source) {
  const std::string name = file.empty() || file == sdf::kSdfStringSource ? source : file;
  return "[" + name + (line ? ":" + std::to_string(*line) : "") + "] ";
}

std::string location(const sdf::ElementPtr& element, const std::string& source) {
  return element ? location(element->FilePath(), element->LineNumber(), source) : location("", {}, source);
}

std::string describe(const sdf::Error& error, const std::string& source) {
  return location(error.FilePath().value_or(""), error.LineNumber(), source) + error.Message();
}

/// Every child element called `name`.
std::vector<sdf::ElementPtr> children(const sdf::ElementPtr& parent, const std::string& name) {
  std::vector<sdf::ElementPtr> found;
  for (sdf::ElementPtr child = parent ? parent->FindElement(name) : nullptr; child;
       child = child->GetNextElement(name)) {
    found.push_back(child);
  }
  return found;
}

/// An sdformat element, with its children, as a TagNode (through its XML text: sdformat keeps a plugin's own
/// tags as elements it does not know).
TagNode tagNodeOf(const sdf::ElementPtr& element) {
  tinyxml2::XMLDocument document;
  const std::string xml = element ? element->ToString("") : "";
  if (document.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS || !document.RootElement()) return {};
  TagNode node = readTagNode(*document.RootElement());
  node.line = element->LineNumber().value_or(0);
  return node;
}

/// A world's models run no plugins: what checks that a non-static one can be a body declares none.
class NoPlugins : public PluginParsers {
 public:
  std::shared_ptr<const PluginConfig> parse(const DeclarationSource&) const override { return nullptr; }
};

/// Turns sdformat's DOM of one world, or of one model to spawn, into specs, collecting every problem in
/// `diagnostics`.
class WorldConverter {
 public:
  WorldConverter(const PackageResolver& resolver, fs::path base_directory, Diagnostics& diagnostics,
                 const Limits& limits)
      : resolver_(resolver),
        base_directory_(std::move(base_directory)),
        diagnostics_(diagnostics),
        limits_(limits) {}

  void convert(const sdf::World& world, WorldSpec& spec) {
    spec.name = world.Name();
    spec.gravity = toEigen(world.Gravity());
    if (!spec.gravity.allFinite()) {
      diagnostics_.error(locate(world.Element()) + "world [" + world.Name() + "]: gravity [" +
                         toText(spec.gravity) + "] is not finite");
      spec.gravity = Eigen::Vector3d(0, 0, -9.81);
    }
    if (const sdf::Physics* physics = world.PhysicsDefault()) {
      convertPhysics(*physics, spec);
      convertOde(*physics, spec.ode);
      noteEngine(*physics);
    }
    if (const ignition::math::SphericalCoordinates* earth = world.SphericalCoordinates()) {
      spec.spherical_coordinates =
          SphericalCoordinates{earth->LatitudeReference().Degree(), earth->LongitudeReference().Degree(),
                               earth->ElevationReference(), earth->HeadingOffset().Radian()};
    }
    for (const auto& plugin : children(world.Element(), "plugin")) {
      diagnostics_.warning(locate(plugin) + "world plugin [" + plugin->Get<std::string>("name") + "] (" +
                           plugin->Get<std::string>("filename") +
                           ") ignored: bullet_sim runs no world plugins");
    }
    for (uint64_t i = 0; i < world.ActorCount(); ++i) {
      diagnostics_.warning("actor [" + world.ActorByIndex(i)->Name() + "] ignored: bullet_sim has no actors");
    }
    // Lights (the sun) matter to no simulated sensor, so they are dropped silently.
    for (uint64_t i = 0; i < world.ModelCount(); ++i) {
      spec.models.push_back(toModelSpec(*world.ModelByIndex(i)));
    }
  }

  /// The model of a model file, to spawn: its joints, sensors and plugins are kept (model plugins first), and
  /// nothing about them is warned of.
  WorldModelSpec toSpawnSpec(const sdf::Model& model) {
    spawning_ = true;
    WorldModelSpec spec = toModelSpec(model);
    spawning_ = false;
    std::stable_partition(spec.plugins.begin(), spec.plugins.end(),
                          [](const PluginElement& plugin) { return !plugin.sensor; });
    return spec;
  }

 private:
  /// The step and the pace. Gazebo paces its steps by <real_time_update_rate> alone (0: as fast as possible);
  /// without one, <real_time_factor> sets the pace.
  void convertPhysics(const sdf::Physics& physics, WorldSpec& spec) {
    const std::string at = locate(physics.Element()) + "physics [" + physics.Name() + "]: ";
    spec.max_step_size = physics.MaxStepSize();
    spec.real_time_factor = physics.RealTimeFactor();
    if (!(spec.max_step_size > 0 && std::isfinite(spec.max_step_size))) {
      diagnostics_.error(at + "max_step_size [" + toText(spec.max_step_size) +
                         "] must be positive; Gazebo's default is 0.001");
      return;
    }
    if (!(spec.real_time_factor >= 0 && std::isfinite(spec.real_time_factor))) {
      diagnostics_.error(at + "real_time_factor [" + toText(spec.real_time_factor) +
                         "] must be >= 0; Gazebo's default is 1");
      return;
    }
    const sdf::ElementPtr element = physics.Element();
    // sdformat fills in the required elements a file leaves out, so only a written one counts.
    const sdf::ElementPtr written = element ? element->FindElement("real_time_update_rate") : nullptr;
    if (!written || !written->GetExplicitlySetInFile()) {
      spec.real_time_update_rate = spec.real_time_factor / spec.max_step_size;
      return;
    }
    const double rate = written->Get<double>();
    if (!(rate >= 0 && std::isfinite(rate))) {
      diagnostics_.error(at + "real_time_update_rate [" + toText(rate) +
                         "] must be >= 0 (0 runs as fast as possible); Gazebo's default is 1000");
      return;
    }
    spec.real_time_update_rate = rate;
    if (std::abs(rate * spec.max_step_size - spec.real_time_factor) > 1e-6 * spec.real_time_factor) {
      diagnostics_.warning(at + "real_time_factor [" + toText(spec.real_time_factor) +
                           "] disagrees with real_time_update_rate [" + toText(rate) + "] x max_step_size [" +
                           toText(spec.max_step_size) + "]: as in Gazebo, the update rate sets the pace (" +
                           (rate > 0 ? toText(rate * spec.max_step_size) + " x real time)"
                                     : "as fast as possible)"));
    }
  }

  /// <physics><ode> and <max_contacts>, kept for get_physics_properties as Gazebo reports them. Bullet's
  /// solver reads none of them, so the ones the file writes are named in one warning.
  void convertOde(const sdf::Physics& physics, OdeSettings& ode) {
    const sdf::ElementPtr element = physics.Element();
    if (!element) return;
    const sdf::ElementPtr ode_element = element->FindElement("ode");
    const sdf::ElementPtr solver = ode_element ? ode_element->FindElement("solver") : nullptr;
    const sdf::ElementPtr constraints = ode_element ? ode_element->FindElement("constraints") : nullptr;
    std::vector<std::string> written;
    const auto read = [&](const sdf::ElementPtr& parent, const std::string& name, auto& value) {
      const sdf::ElementPtr child = parent ? parent->FindElement(name) : nullptr;
      if (!child) return;
      const auto given = child->Get<std::decay_t<decltype(value)>>();
      if (!std::isfinite(static_cast<double>(given))) {
        diagnostics_.error(locate(child) + name + " [" + toText(given) + "] is not finite");
        return;
      }
      value = given;
      if (child->GetExplicitlySetInFile()) written.push_back(name + " [" + toText(value) + "]");
    };
    read(solver, "iters", ode.iters);
    read(solver, "precon_iters", ode.precon_iters);
    read(solver, "sor", ode.sor);
    read(constraints, "cfm", ode.cfm);
    read(constraints, "erp", ode.erp);
    read(constraints, "contact_max_correcting_vel", ode.contact_max_correcting_vel);
    read(constraints, "contact_surface_layer", ode.contact_surface_layer);
    read(element, "max_contacts", ode.max_contacts);
    if (written.empty()) return;
    diagnostics_.warning(locate(element) + "physics [" + physics.Name() + "]: the ODE settings " +
                         joinedNames(written) +
                         " are reported by get_physics_properties, as Gazebo reports them, but not used: "
                         "bullet_sim's contacts are Bullet's");
  }

  /// A world written for Gazebo's DART or Simbody engine steps on Bullet here: one warning says so.
  void noteEngine(const sdf::Physics& physics) {
    const std::string type = physics.EngineType();
    if (type == "ode" || type == "bullet") return;
    diagnostics_.warning(locate(physics.Element()) + "physics [" + physics.Name() + "] type [" + type +
                         "]: bullet_sim steps every world with Bullet (its contacts and solver are "
                         "Bullet's); the <" + type + "> settings are not read");
  }

  /// "[file:line] " of an element, for messages.
  std::string locate(const sdf::ElementPtr& element) const {
    return location(element, diagnostics_.source());
  }

  WorldModelSpec toModelSpec(const sdf::Model& model) {
    WorldModelSpec spec;
    spec.name = model.Name();
    spec.pose = resolvePose(model.SemanticPose(), "", "model [" + model.Name() + "]", model.Element());
    spec.is_static = model.Static();
    if (model.Element()) spec.allow_auto_disable = model.Element()->Get<bool>("allow_auto_disable");
    addContents(model, Eigen::Isometry3d::Identity(), model.Name(), spec);
    if (!spec.is_static && !spawning_) checkBody(model, spec);
    return spec;
  }

  /// A world's non-static model is a body, jointed as its file says, when bullet_sim can simulate it as one;
  /// else a static obstacle, with one warning that says why.
  void checkBody(const sdf::Model& model, WorldModelSpec& spec) {
    Diagnostics body(diagnostics_.source());
    bullet_sim::toModelSpec(spec, NoPlugins(), body, limits_, /*weld_unjoined=*/true);
    for (const Collision& collision : spec.collisions) {
      if (collision.shape.type == Shape::Type::kPlane)
        body.error("collision [" + collision.name + "] is a plane, which only static geometry may have");
    }
    const std::string at = locate(model.Element()) + "model [" + model.Name() + "]";
    for (const std::string& warning : body.warnings()) diagnostics_.warning(at + ": " + warning);
    if (body.errors().empty()) return;
    diagnostics_.warning(at + " is not static, but bullet_sim cannot simulate it as a body (" +
                         joined(body.errors(), "; ") +
                         "): it is a static obstacle, as if it were <static>");
    spec.is_static = true;
    spec.joints.clear();
  }

  /// Adds the links, collisions and visuals of `model` (the top-level model or one nested in it, placed at
  /// `in_top_model`) to `spec`, and, for a model to spawn, its joints and plugins. `scope` is its name for
  /// messages, e.g. "house::door".
  void addContents(const sdf::Model& model, const Eigen::Isometry3d& in_top_model, const std::string& scope,
                   WorldModelSpec& spec) {
    const std::string prefix = scope == spec.name ? "" : scope.substr(spec.name.size() + 2) + "::";
    if (spawning_ || !spec.is_static) {
      for (uint64_t j = 0; j < model.JointCount(); ++j) {
        addJoint(*model.JointByIndex(j), in_top_model, prefix, spec);
      }
    } else if (model.JointCount() > 0) {
      std::string joints;
      for (uint64_t i = 0; i < model.JointCount(); ++i) {
        joints += (i ? ", [" : "[") + model.JointByIndex(i)->Name() + "]";
      }
      diagnostics_.warning(locate(model.Element()) + "model [" + scope + "]: joints " + joints +
                           " ignored: the model is <static>, so they do not move");
    }
    for (const auto& plugin : children(model.Element(), "plugin")) {
      if (spawning_) {
        spec.plugins.push_back({tagNodeOf(plugin), std::nullopt, std::nullopt, locate(plugin)});
      } else {
        diagnostics_.warning(locate(plugin) + "model [" + scope + "]: plugin [" +
                             plugin->Get<std::string>("name") + "] ignored: world models run no plugins");
      }
    }
    for (uint64_t l = 0; l < model.LinkCount(); ++l) {
      addLink(*model.LinkByIndex(l), in_top_model, scope, prefix, spec);
    }
    for (uint64_t m = 0; m < model.ModelCount(); ++m) {
      const sdf::Model& nested = *model.ModelByIndex(m);
      const std::string nested_scope = scope + "::" + nested.Name();
      const Eigen::Isometry3d nested_pose =
          in_top_model *
          resolvePose(nested.SemanticPose(), "", "model [" + nested_scope + "]", nested.Element());
      addContents(nested, nested_pose, nested_scope, spec);
    }
  }

  void addLink(const sdf::Link& link, const Eigen::Isometry3d& in_top_model, const std::string& scope,
               const std::string& prefix, WorldModelSpec& spec) {
    const std::string owner = "model [" + scope + "] link [" + link.Name() + "]";
    WorldLinkSpec& placed = spec.links.emplace_back();
    placed.name = prefix + link.Name();
    placed.pose = in_top_model * resolvePose(link.SemanticPose(), "__model__", owner, link.Element());
    readBody(link, placed);
    for (uint64_t s = 0; s < link.SensorCount(); ++s) {
      if (spawning_) {
        addSensor(*link.SensorByIndex(s), placed.name, owner, spec);
      } else {
        diagnostics_.warning(locate(link.Element()) + owner + ": sensor [" + link.SensorByIndex(s)->Name() +
                             "] ignored: world models have no sensors");
      }
    }
    if (!withinShapeLimit(link.CollisionCount() + link.VisualCount())) return;
    for (uint64_t c = 0; c < link.CollisionCount(); ++c) {
      const sdf::Collision& collision = *link.CollisionByIndex(c);
      const std::string where = owner + " collision [" + collision.Name() + "]";
      placed.collisions.push_back(collision.Name());
      const SurfaceSpec surface = surfaceOf(collision);
      if (c == 0) placed.surface = surface;
      std::optional<Shape> shape = toShape(*collision.Geom(), where);
      if (!shape) continue;
      Collision result;
      result.origin =
          in_top_model * resolvePose(collision.SemanticPose(), "__model__", where, collision.Element());
      result.shape = std::move(*shape);
      result.name = scope + "::" + link.Name() + "::" + collision.Name();
      result.mu = surface.mu1;
      placed.collision_indices.push_back(spec.collisions.size());
      spec.collisions.push_back(std::move(result));
    }
    for (uint64_t v = 0; v < link.VisualCount(); ++v) {
      const sdf::Visual& visual = *link.VisualByIndex(v);
      const std::string where = owner + " visual [" + visual.Name() + "]";
      std::optional<Shape> shape = toShape(*visual.Geom(), where);
      if (!shape) continue;
      Visual result;
      result.origin = in_top_model * resolvePose(visual.SemanticPose(), "__model__", where, visual.Element());
      result.shape = std::move(*shape);
      if (result.shape.type == Shape::Type::kPlane) standInForPlane(*visual.Geom()->PlaneShape(), result);
      applyMaterial(visual, where, result);
      placed.visual_indices.push_back(spec.visuals.size());
      spec.visuals.push_back(std::move(result));
    }
  }

  /// A link's <inertial> (SDF's default when it has none: 1 kg, unit moments), <gravity> and <self_collide>.
  static void readBody(const sdf::Link& link, WorldLinkSpec& placed) {
    const ignition::math::Inertiald& inertial = link.Inertial();
    const Eigen::Isometry3d frame = toIsometry(inertial.Pose());
    const ignition::math::Matrix3d moments = inertial.MassMatrix().Moi();
    Eigen::Matrix3d tensor;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) tensor(r, c) = moments(r, c);
    }
    placed.inertial = InertialSpec{inertial.MassMatrix().Mass(), frame.translation(),
                                   frame.linear() * tensor * frame.linear().transpose()};
    if (const sdf::ElementPtr element = link.Element()) {
      placed.gravity = element->Get<bool>("gravity");
      placed.self_collide = element->Get<bool>("self_collide");
    }
  }

  /// <surface><friction><ode> mu and mu2, Gazebo's defaults (1) where they are not given (a negative one is
  /// unlimited: rewriteSdf9Values rewrote it).
  static SurfaceSpec surfaceOf(const sdf::Collision& collision) {
    sdf::ElementPtr ode = collision.Element();
    for (const char* name : {"surface", "friction", "ode"}) {
      ode = ode && ode->HasElement(name) ? ode->GetElement(name) : nullptr;
    }
    SurfaceSpec surface;
    if (ode && ode->HasElement("mu")) surface.mu1 = ode->Get<double>("mu");
    if (ode && ode->HasElement("mu2")) surface.mu2 = ode->Get<double>("mu2");
    return surface;
  }

  void addJoint(const sdf::Joint& joint, const Eigen::Isometry3d& in_top_model, const std::string& prefix,
                WorldModelSpec& spec) {
    const std::string owner = "model [" + spec.name + "] joint [" + prefix + joint.Name() + "]";
    static const std::map<sdf::JointType, JointSpec::Type> kTypes = {
        {sdf::JointType::FIXED, JointSpec::Type::kFixed},
        {sdf::JointType::REVOLUTE, JointSpec::Type::kRevolute},
        {sdf::JointType::CONTINUOUS, JointSpec::Type::kContinuous},
        {sdf::JointType::PRISMATIC, JointSpec::Type::kPrismatic}};
    const auto type = kTypes.find(joint.Type());
    const std::string type_name = joint.Element() ? joint.Element()->Get<std::string>("type") : "";
    if (type == kTypes.end() && spawning_) {
      diagnostics_.error(locate(joint.Element()) + owner + ": type [" + type_name +
                         "] is not supported; use fixed, revolute, continuous or prismatic");
      return;
    }
    if (type == kTypes.end()) {  // a world's model still loads, as in Gazebo, with the joint rigid
      diagnostics_.warning(locate(joint.Element()) + owner + ": type [" + type_name +
                           "] is not simulated (bullet_sim has fixed, revolute, continuous and prismatic "
                           "joints): it is held fixed");
    }
    WorldJointSpec& placed = spec.joints.emplace_back();
    placed.name = prefix + joint.Name();
    placed.type = type == kTypes.end() ? JointSpec::Type::kFixed : type->second;
    placed.parent = joint.ParentLinkName() == "world" ? "world" : prefix + joint.ParentLinkName();
    placed.child = prefix + joint.ChildLinkName();
    placed.pose = in_top_model * resolvePose(joint.SemanticPose(), "__model__", owner, joint.Element());
    const sdf::JointAxis* axis = joint.Axis(0);
    if (!axis || placed.type == JointSpec::Type::kFixed) return;
    ignition::math::Vector3d xyz;
    for (const sdf::Error& error : axis->ResolveXyz(xyz, "__model__")) {
      diagnostics_.error(locate(joint.Element()) + owner + ": cannot resolve its axis: " + error.Message());
    }
    placed.axis = in_top_model.linear() * toEigen(xyz);
    if (!(placed.axis.norm() > 1e-9)) {
      diagnostics_.error(locate(joint.Element()) + owner + ": <axis><xyz> is zero: give it a direction");
    } else {
      placed.axis.normalize();
    }
    // SDF writes "no limit" as +-1e16, and -1 for no effort or velocity limit.
    constexpr double kNoLimit = 1e16;
    placed.lower = axis->Lower() <= -kNoLimit ? -std::numeric_limits<double>::infinity() : axis->Lower();
    placed.upper = axis->Upper() >= kNoLimit ? std::numeric_limits<double>::infinity() : axis->Upper();
    placed.effort = std::max(0.0, axis->Effort());
    placed.velocity = std::max(0.0, axis->MaxVelocity());
    placed.damping = axis->Damping();
    placed.friction = axis->Friction();
    for (auto [term, value] :
         {std::pair{"damping", &placed.damping}, std::pair{"friction", &placed.friction}}) {
      if (!(*value < 0)) continue;  // a negative one as a URDF's (urdf_values.cpp)
      diagnostics_.warning(locate(joint.Element()) + owner + ": <dynamics><" + term + "> [" + toText(*value) +
                           "] is negative: read as 0");
      *value = 0;
    }
  }

  /// A sensor of a model to spawn, with its <plugin>: the plugin registry reads both, as for a URDF's.
  void addSensor(const sdf::Sensor& sensor, const std::string& link, const std::string& owner,
                 WorldModelSpec& spec) {
    const std::string where = owner + " sensor [" + sensor.Name() + "]";
    SensorDeclaration declared;
    declared.name = sensor.Name();
    declared.link = link;
    declared.pose = resolvePose(sensor.SemanticPose(), "", where, sensor.Element());  // in its link's frame
    declared.update_rate = sensorUpdateRate(sensor.UpdateRate(), locate(sensor.Element()) + where + " ",
                                            diagnostics_);
    TagNode tags = tagNodeOf(sensor.Element());
    declared.type = tags.attribute("type");
    const TagNode* plugin = tags.child("plugin");
    if (!plugin) {
      diagnostics_.warning("sensor [" + sensor.Name() + "] on link [" + link +
                           "] has no <plugin>, so Gazebo publishes nothing from it: ignored");
      return;
    }
    const TagNode plugin_tags = *plugin;
    spec.plugins.push_back({plugin_tags, declared, std::move(tags), locate(sensor.Element()) + where + " "});
  }

  /// The pose of an element relative to frame `relative_to` ("" for its default frame): finite, and
  /// within max_length of it.
  Eigen::Isometry3d resolvePose(const sdf::SemanticPose& semantic_pose, const std::string& relative_to,
                                const std::string& owner, const sdf::ElementPtr& element) {
    ignition::math::Pose3d pose;
    for (const sdf::Error& error : semantic_pose.Resolve(pose, relative_to)) {
      diagnostics_.error(locate(element) + owner + ": cannot resolve its pose: " + error.Message());
    }
    const Eigen::Isometry3d result = toIsometry(pose);
    for (int i = 0; i < 3; ++i) {
      if (auto problem = boundProblem(result.translation()[i], limits_.max_length, "max_length", "m")) {
        diagnostics_.error(locate(element) + owner + ": its position " + "xyz"[i] + " " + *problem);
        return Eigen::Isometry3d::Identity();
      }
    }
    if (!result.linear().allFinite()) {
      diagnostics_.error(locate(element) + owner +
                         ": its orientation is not a rotation (a zero quaternion?)");
      return Eigen::Isometry3d::Identity();
    }
    return result;
  }

  /// False, after one error, once the collisions and visuals would pass max_world_shapes (of a world) or
  /// max_shapes (of a model to spawn).
  bool withinShapeLimit(size_t more) {
    shapes_ += more;
    const size_t limit = spawning_ ? limits_.max_shapes : limits_.max_world_shapes;
    if (shapes_ <= limit) return true;
    if (!reported_shapes_) {
      diagnostics_.error(std::string(spawning_ ? "the model" : "the world") + " has more than " +
                         std::to_string(limit) + " collisions and visuals, the limit (" +
                         (spawning_ ? "max_shapes" : "max_world_shapes") +
                         "): is it generated by mistake? Raise the limit if it is meant");
    }
    reported_shapes_ = true;
    return false;
  }

  /// An error when a size is beyond max_length: nullopt then.
  std::optional<Shape> withinLength(Shape shape, const std::string& at) {
    const double largest = std::max({shape.box_size.maxCoeff(), shape.radius, shape.length});
    if (auto problem = boundProblem(largest, limits_.max_length, "max_length", "m")) {
      diagnostics_.error(at + ": size " + *problem);
      return std::nullopt;
    }
    return shape;
  }

  /// A plane visual becomes a thin box of the plane's size, top face on the plane: a renderer needs an
  /// extent.
  static void standInForPlane(const sdf::Plane& plane, Visual& visual) {
    const Eigen::Vector3d normal = visual.shape.plane_normal;
    visual.origin.rotate(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal));
    visual.origin.translate(Eigen::Vector3d(0, 0, -kPlaneVisualThickness / 2));
    visual.shape.type = Shape::Type::kBox;
    visual.shape.box_size = Eigen::Vector3d(plane.Size().X(), plane.Size().Y(), kPlaneVisualThickness);
  }

  /// Colour precedence as in Gazebo classic: an explicit <diffuse> (else <ambient>) overrides the script's.
  /// A known script replaces a mesh's own materials; a colour alone tints them.
  void applyMaterial(const sdf::Visual& visual, const std::string& where, Visual& result) {
    if (const sdf::Material* material = visual.Material()) {
      const bool has_diffuse = material->Element()->HasElement("diffuse");
      const bool has_ambient = material->Element()->HasElement("ambient");
      if (has_diffuse || has_ambient) result.paint = MeshPaint::kTint;
      const std::string script = material->ScriptName();
      if (!script.empty()) {
        result.material = script;
        std::optional<Eigen::Vector4d> colour = gazeboMaterialColour(script);
        if (!colour) colour = scriptColour(material->Element(), script, where);
        if (colour) {
          result.rgba = *colour;
          result.paint = MeshPaint::kUniform;
        } else if (!has_diffuse && !has_ambient && unknown_materials_.insert(script).second) {
          diagnostics_.warning(locate(material->Element()) + where + ": unknown Gazebo material [" + script +
                               "]" + didYouMean(script, gazeboMaterialNames()) +
                               ": no script of its <uri>s or of Gazebo's resource path defines it with a "
                               "colour, so a mesh keeps its own colours and other shapes are grey; give the "
                               "visual a <diffuse> colour (warned once for all visuals that use it)");
        }
      }
      if (has_diffuse) {
        result.rgba = toRgba(material->Diffuse());
      } else if (has_ambient) {
        result.rgba = toRgba(material->Ambient());
      }
    }
    result.rgba[3] *= 1.0 - visual.Transparency();
  }

  /// The colour material scripts give `script`: those its <uri>s name, then those of the resource path; its
  /// texture looked for in its <uri>s' folders, then the resource path's. A texture that cannot be used is
  /// warned about once per name. Visuals naming the same scripts share one reading of them and of the
  /// texture.
  std::optional<Eigen::Vector4d> scriptColour(const sdf::ElementPtr& material, const std::string& script,
                                              const std::string& where) {
    std::vector<std::string> folders;
    const std::vector<std::string> scripts = materialScripts(material, folders);
    std::string key = script;
    for (const std::string& file : scripts) key += "\n" + file;
    const auto cached = script_colours_.find(key);
    if (cached != script_colours_.end()) return cached->second;
    const std::vector<std::string> resource = resourceTextureFolders(resolver_.gazeboPaths().resourcePath());
    folders.insert(folders.end(), resource.begin(), resource.end());
    std::string warning;
    std::optional<Eigen::Vector4d> colour = scriptMaterialColour(script, scripts, folders, &warning);
    if (!colour && warning.empty())
      colour = scriptMaterialColour(script, resourceScripts(), folders, &warning);
    if (!warning.empty() && unknown_materials_.insert(script).second) {
      diagnostics_.warning(
          locate(material) + where + ": material [" + script + "]: " + warning +
          (colour ? "; drawn in its colour" : "; a mesh keeps its own colours, other shapes are grey") +
          " (warned once for all visuals that use it)");
    }
    script_colours_[key] = colour;
    return colour;
  }

  /// The .material files that the <uri>s of a material's <script> name: a file, or the .material files of a
  /// folder. model:// and package:// URIs go through the resolver; others (file://media/materials/...) are
  /// looked up in the resource path's folders, then beside the SDF file. `folders` gets the folders the
  /// <uri>s name (a file's own folder), where textures are looked for.
  std::vector<std::string> materialScripts(const sdf::ElementPtr& material,
                                           std::vector<std::string>& folders) const {
    std::vector<std::string> files;
    const sdf::ElementPtr script = material->HasElement("script") ? material->GetElement("script") : nullptr;
    for (const auto& uri : children(script, "uri")) {
      std::string text = uri->Get<std::string>();
      std::vector<fs::path> candidates;
      if (hasScheme(text, "model") || hasScheme(text, "package")) {
        std::string ignored;
        if (const auto resolved = resolver_.resolve(text, &ignored)) candidates.emplace_back(*resolved);
      } else {
        if (hasScheme(text, "file")) text = text.substr(std::string("file://").size());
        for (const auto& folder : resolver_.gazeboPaths().resourcePath())
          candidates.push_back(fs::path(folder) / text);
        candidates.push_back(base_directory_ / text);
      }
      if (const std::optional<fs::path> found = appendScripts(candidates, files)) {
        std::error_code ec;
        folders.push_back(fs::is_directory(*found, ec) ? found->string() : found->parent_path().string());
      }
    }
    return files;
  }

  /// The scripts of Gazebo's resource path, which every visual sees, read from disk once.
  const std::vector<std::string>& resourceScripts() {
    if (!resource_scripts_)
      resource_scripts_ = resourceMaterialScripts(resolver_.gazeboPaths().resourcePath());
    return *resource_scripts_;
  }

  /// Appends the first of `candidates` that exists: a file, or the .material files of a folder (sorted).
  /// Returns it; nullopt when none exists.
  static std::optional<fs::path> appendScripts(const std::vector<fs::path>& candidates,
                                               std::vector<std::string>& files) {
    std::error_code ec;
    for (const auto& candidate : candidates) {
      if (fs::is_regular_file(candidate, ec)) {
        files.push_back(candidate.string());
        return candidate;
      }
      if (!fs::is_directory(candidate, ec)) continue;
      const std::vector<std::string> scripts = materialScriptsIn(candidate.string());
      files.insert(files.end(), scripts.begin(), scripts.end());
      return candidate;
    }
    return std::nullopt;
  }

  std::optional<Shape> toShape(const sdf::Geometry& geometry, const std::string& where) {
    const std::string at = locate(geometry.Element()) + where;
    Shape shape;
    switch (geometry.Type()) {
      case sdf::GeometryType::BOX:
        shape.type = Shape::Type::kBox;
        shape.box_size = toEigen(geometry.BoxShape()->Size());
        if (!(shape.box_size.minCoeff() > 0)) {
          return invalidSize(at + ": box size [" + toText(shape.box_size) + "]");
        }
        return withinLength(shape, at);
      case sdf::GeometryType::CYLINDER:
        shape.type = Shape::Type::kCylinder;
        shape.radius = geometry.CylinderShape()->Radius();
        shape.length = geometry.CylinderShape()->Length();
        if (!(shape.radius > 0 && shape.length > 0)) {
          return invalidSize(at + ": cylinder radius [" + toText(shape.radius) + "] and length [" +
                             toText(shape.length) + "]");
        }
        return withinLength(shape, at);
      case sdf::GeometryType::SPHERE:
        shape.type = Shape::Type::kSphere;
        shape.radius = geometry.SphereShape()->Radius();
        if (!(shape.radius > 0)) return invalidSize(at + ": sphere radius [" + toText(shape.radius) + "]");
        return withinLength(shape, at);
      case sdf::GeometryType::PLANE:
        shape.type = Shape::Type::kPlane;
        shape.plane_normal = toEigen(geometry.PlaneShape()->Normal());
        if (!(shape.plane_normal.norm() > 0) || !shape.plane_normal.allFinite())
          return invalidSize(at + ": plane normal [" + toText(shape.plane_normal) + "]");
        shape.plane_normal.normalize();
        return shape;
      case sdf::GeometryType::MESH:
        return toMeshShape(*geometry.MeshShape(), geometry.Element(), at);
      case sdf::GeometryType::EMPTY:
      case sdf::GeometryType::HEIGHTMAP:
      case sdf::GeometryType::CAPSULE:
      case sdf::GeometryType::ELLIPSOID:
        break;
    }
    // sdformat 12 reports <polyline> as EMPTY too, so the element's name tells what it really is.
    const sdf::ElementPtr kind = geometry.Element() ? geometry.Element()->GetFirstElement() : nullptr;
    if (!kind || kind->GetName() == "empty") return std::nullopt;
    diagnostics_.error(
        at + ": unsupported geometry [" + kind->GetName() +
        "]; bullet_sim supports box, cylinder, sphere, plane and mesh: replace it with one of them");
    return std::nullopt;
  }

  std::optional<Shape> toMeshShape(const sdf::Mesh& mesh, const sdf::ElementPtr& geometry_element,
                                   const std::string& at) {
    // Relative mesh paths start at the SDF file that holds the mesh (an included model's own file).
    std::error_code ec;
    const fs::path defined_in = geometry_element ? fs::path(geometry_element->FilePath()) : fs::path();
    const fs::path base_directory =
        fs::is_regular_file(defined_in, ec) ? fs::absolute(defined_in).parent_path() : base_directory_;

    std::string error;
    const std::optional<fs::path> path = resolveFile(mesh.Uri(), resolver_, base_directory, &error);
    if (!path) {
      if (spawning_ || !supportedScheme(mesh.Uri())) {
        diagnostics_.error(at + ": mesh [" + mesh.Uri() + "]: " + error);
      } else {
        skipMissingMesh(mesh.Uri(), at, error);
      }
      return std::nullopt;
    }
    if (!mesh.Submesh().empty()) {
      diagnostics_.warning(at + ": submesh [" + mesh.Submesh() + "] ignored: the whole mesh is loaded");
    }
    Shape shape;
    shape.type = Shape::Type::kMesh;
    shape.mesh_path = fs::absolute(*path).lexically_normal().string();
    shape.mesh_scale = toEigen(mesh.Scale());
    std::vector<std::string> warnings;
    shape.mesh = meshes_.load(shape.mesh_path, shape.mesh_scale, &error, &warnings);
    for (const std::string& warning : warnings) diagnostics_.warning(at + ": " + warning);
    if (!shape.mesh) {
      diagnostics_.error(at + ": " + error + "; check that the file is an STL, DAE or OBJ mesh");
      return std::nullopt;
    }
    triangles_ += shape.mesh->triangles.size();
    if (triangles_ > limits_.max_triangles) {
      diagnostics_.error(at + ": mesh [" + shape.mesh_path + "] brings the meshes to " +
                         std::to_string(triangles_) + " triangles, above the limit of " +
                         std::to_string(limits_.max_triangles) + " (max_triangles): simplify the meshes");
      return std::nullopt;
    }
    return shape;
  }

  /// A world's shape whose mesh cannot be found is skipped, as gzserver skips it (it logs an error and loads
  /// the rest), with one warning per mesh URI; an error when the load is strict (~strict_models).
  void skipMissingMesh(const std::string& uri, const std::string& at, const std::string& why) {
    // model:///x and model://x are one mesh (see PackageResolver::resolve).
    const size_t slashes = hasScheme(uri, "model")
                               ? uri.find_first_not_of('/', std::string("model://").size())
                               : std::string::npos;
    const std::string key = slashes == std::string::npos ? uri : "model://" + uri.substr(slashes);
    if (!missing_meshes_.insert(key).second) return;
    if (diagnostics_.strict()) {
      diagnostics_.error(at + ": mesh [" + uri + "] cannot be found (~strict_models is set): " + why);
      return;
    }
    diagnostics_.warning(at + ": mesh [" + uri + "] cannot be found, so this shape and every other one " +
                         "with that mesh are skipped, as Gazebo skips them (a collision skipped is one " +
                         "nothing touches); the rest of the world loads: " + why);
  }

  std::nullopt_t invalidSize(const std::string& what) {
    diagnostics_.error(what + " must be positive; fix the size in the SDF");
    return std::nullopt;
  }

  const PackageResolver& resolver_;
  const fs::path base_directory_;  // for relative paths in SDF text that has no file
  Diagnostics& diagnostics_;
  const Limits& limits_;
  MeshCache meshes_{limits_};                // copies of a model share their meshes and textures
  std::set<std::string> unknown_materials_;  // Gazebo material names warned about, once each
  std::set<std::string> missing_meshes_;     // mesh URIs that cannot be found, warned about once each
  std::optional<std::vector<std::string>> resource_scripts_;              // see resourceScripts
  std::map<std::string, std::optional<Eigen::Vector4d>> script_colours_;  // see scriptColour
  bool spawning_ = false;  ///< converting a model to spawn, not a world's
  size_t shapes_ = 0;      ///< collisions and visuals so far
  bool reported_shapes_ = false;
  size_t triangles_ = 0;  ///< of every mesh shape so far
};

/// libsdformat's find callback for <include> URIs: a model:// include, or any URI that names a folder,
/// becomes the SDF file that the folder's model.config names; other URIs go through `resolveFile`. It
/// remembers why a URI could not be found.
class IncludeFinder {
 public:
  IncludeFinder(const PackageResolver& resolver, fs::path base_directory)
      : resolver_(resolver), base_directory_(std::move(base_directory)) {}

  std::string operator()(const std::string& uri) {
    std::string error;
    if (hasScheme(uri, "model") && uri.find('/', std::string("model://").size()) == std::string::npos) {
      const std::string name = uri.substr(std::string("model://").size());
      const std::optional<std::string> folder = resolver_.gazeboPaths().findModelFile(name, &error);
      if (!folder) {
        unknown_models_[uri] = error;
      } else if (const std::optional<std::string> file = modelSdfFile(*folder, &error)) {
        return *file;
      } else {
        unresolved_[uri] = error;
      }
    } else if (const std::optional<fs::path> path = resolveFile(uri, resolver_, base_directory_, &error)) {
      // A folder is a model folder, whose model.config names the SDF file.
      std::error_code ec;
      if (!fs::is_directory(*path, ec)) return path->string();
      if (const std::optional<std::string> file = modelSdfFile(path->string(), &error)) return *file;
      unresolved_[uri] = error;
    } else {
      unresolved_[uri] = error;
    }
    return "";  // sdformat then reports the include as unresolved
  }

  /// Include URI -> why it could not be found, for models that are on no folder of the model path.
  const std::map<std::string, std::string>& unknownModels() const { return unknown_models_; }
  /// Include URI -> why it could not be resolved, for every other include.
  const std::map<std::string, std::string>& unresolved() const { return unresolved_; }

 private:
  const PackageResolver& resolver_;
  const fs::path base_directory_;
  std::map<std::string, std::string> unknown_models_;
  std::map<std::string, std::string> unresolved_;
};

/// Reports libsdformat's errors. An include of an unknown model is skipped, as Gazebo skips it, with one
/// warning per model (an error when `options.strict_models`); any other unresolved include is an error that
/// says why.
void reportLoadErrors(const sdf::Errors& errors, const IncludeFinder& finder, const WorldOptions& options,
                      Diagnostics& diagnostics) {
  std::map<std::string, std::string> unresolved = finder.unresolved();
  std::map<std::string, int> unknown_includes;  // URI -> how many includes name it
  std::map<std::string, std::string> first_location;
  const auto mentions = [](const sdf::Error& error, const std::string& uri) {
    return error.Message().find("[" + uri + "]") != std::string::npos;
  };
  for (const sdf::Error& error : errors) {
    const auto unknown = std::find_if(finder.unknownModels().begin(), finder.unknownModels().end(),
                                      [&](const auto& entry) { return mentions(error, entry.first); });
    if (unknown != finder.unknownModels().end()) {
      if (unknown_includes[unknown->first]++ == 0) {
        first_location[unknown->first] =
            location(error.FilePath().value_or(""), error.LineNumber(), diagnostics.source());
      }
      continue;
    }
    std::string message = describe(error, diagnostics.source());
    for (auto it = unresolved.begin(); it != unresolved.end();) {
      if (!mentions(error, it->first)) {
        ++it;
        continue;
      }
      message += ": " + it->second;
      it = unresolved.erase(it);
    }
    diagnostics.error(message);
  }
  for (const auto& [uri, reason] : unresolved) diagnostics.error("include [" + uri + "]: " + reason);
  for (const auto& [uri, count] : unknown_includes) {
    const std::string& reason = finder.unknownModels().at(uri);
    if (options.strict_models) {
      diagnostics.error(first_location[uri] + reason + " (~strict_models is set)");
    } else {
      const std::string times = count > 1 ? " (" + std::to_string(count) + " includes)" : "";
      diagnostics.warning(first_location[uri] + "skipped" + times +
                          ", the rest of the world loads: " + reason);
    }
  }
}

/// One reading of a world or of a model to spawn: what it holds, and its problems.
struct Reading {
  WorldSpec spec;
  Diagnostics diagnostics;
};

using Load = std::function<sdf::Errors(sdf::Root&, const sdf::ParserConfig&)>;

/// Runs `load` (from a file or from text), or reads `copies->reduced_text` when given, with `resolver` behind
/// <include>, then converts the world, or with `model_to_spawn` the one model of a model's SDF.
/// `base_directory` is where relative include and mesh paths start.
Reading readWorld(const WorldCopies* copies, const Load& load, const std::string& source,
                  const fs::path& base_directory, const PackageResolver& resolver,
                  const WorldOptions& options, bool model_to_spawn) {
  Reading reading{WorldSpec(), Diagnostics(source, options.strict_models)};
  Diagnostics& diagnostics = reading.diagnostics;
  IncludeFinder finder(resolver, base_directory);
  sdf::ParserConfig config;
  config.SetFindCallback(std::ref(finder));

  sdf::Root root;
  const sdf::Errors errors = copies ? root.LoadSdfString(copies->reduced_text, config) : load(root, config);
  reportLoadErrors(errors, finder, options, diagnostics);
  reading.spec.source = source;
  WorldConverter converter(resolver, base_directory, diagnostics, options.limits);
  if (model_to_spawn) {
    if (const sdf::Model* model = root.Model()) {
      reading.spec.models.push_back(converter.toSpawnSpec(*model));
    } else if (errors.empty()) {
      diagnostics.error(
          "no <model> element; a model to spawn holds <sdf version=\"1.6\"><model name=\"...\">");
    }
    return reading;
  }
  if (root.WorldCount() == 0) {
    if (errors.empty()) {
      diagnostics.error("no <world> element; a world file holds <sdf version=\"1.6\"><world name=\"...\">");
    }
    return reading;
  }
  if (root.WorldCount() > 1) {
    diagnostics.warning("only the first of " + std::to_string(root.WorldCount()) + " worlds, [" +
                        root.WorldByIndex(0)->Name() + "], is loaded");
  }
  converter.convert(*root.WorldByIndex(0), reading.spec);
  if (copies) addCopies(*copies, options.limits, reading.spec, diagnostics);
  return reading;
}

/// Reads a world, or a model to spawn, from `text`, which `load` loads into sdformat (from a file or from the
/// text itself).
WorldSpec parseWith(const std::string& text, const Load& load, const std::string& source,
                    const fs::path& base_directory, const PackageResolver& resolver,
                    std::vector<std::string>* warnings, const WorldOptions& options,
                    bool model_to_spawn = false) {
  // sdformat 12 reports malformed XML only as "Unable to read file" (the detail goes to stderr), so tinyxml2
  // checks it first and names the line and the element.
  tinyxml2::XMLDocument xml;
  if (xml.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS) {
    throw SpecError(source, {"[" + source + ":" + std::to_string(xml.ErrorLineNum()) +
                             "] malformed XML: " + xml.ErrorStr() + "; fix the XML there"});
  }
  std::string rewritten = text;  // sdformat 12 refuses values that Gazebo's sdformat 9 reads
  if (const auto rewrites = rewriteSdf9Values(xml, source, rewritten); !rewrites.empty()) {
    if (warnings) warnings->insert(warnings->end(), rewrites.begin(), rewrites.end());
    const Load load_rewritten = [&](sdf::Root& root, const sdf::ParserConfig& config) {
      return root.LoadSdfString(rewritten, config);
    };
    return parseWith(rewritten, load_rewritten, source, base_directory, resolver, warnings, options,
                     model_to_spawn);
  }
  // Models that repeat another's contents are read once. Should anything be wrong, the whole file is read
  // again, so that every problem is reported where it is.
  const std::optional<WorldCopies> copies = model_to_spawn ? std::nullopt : findCopies(xml);
  Reading reading = readWorld(copies ? &*copies : nullptr, load, source, base_directory, resolver, options,
                              model_to_spawn);
  if (copies && !reading.diagnostics.errors().empty())
    reading = readWorld(nullptr, load, source, base_directory, resolver, options, model_to_spawn);
  const auto& said = reading.diagnostics.warnings();
  if (warnings) warnings->insert(warnings->end(), said.begin(), said.end());
  reading.diagnostics.throwIfErrors();
  return std::move(reading.spec);
}

void checkSize(const std::string& text, const std::string& source, const Limits& limits) {
  if (text.size() > limits.max_description_bytes) {
    throw SpecError(source, {"the SDF is " + std::to_string(text.size()) + " bytes, above the limit of " +
                             std::to_string(limits.max_description_bytes) + " (max_description_bytes)"});
  }
}

}  // namespace

WorldSpec loadWorldHere(const std::string& path, const PackageResolver& resolver,
                        std::vector<std::string>* warnings, const WorldOptions& options) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw SpecError(path, {"no such file [" + path + "]; check the path (a relative one starts at [" +
                           fs::current_path(ec).string() + "])"});
  }
  std::string text;
  try {
    text = readRegularFile(path, options.limits.max_description_bytes, "max_description_bytes");
  } catch (const std::runtime_error& e) {
    throw SpecError(path, {std::string("the world file ") + e.what()});
  }
  return parseWith(
      text, [&](sdf::Root& root, const sdf::ParserConfig& config) { return root.Load(path, config); }, path,
      fs::absolute(path, ec).parent_path(), resolver, warnings, options);
}

WorldSpec parseWorldHere(const std::string& sdf_text, const std::string& source,
                         const PackageResolver& resolver, std::vector<std::string>* warnings,
                         const WorldOptions& options) {
  checkSize(sdf_text, source, options.limits);
  std::error_code ec;
  return parseWith(
      sdf_text,
      [&](sdf::Root& root, const sdf::ParserConfig& config) { return root.LoadSdfString(sdf_text, config); },
      source, fs::absolute(source, ec).parent_path(), resolver, warnings, options);
}

WorldModelSpec readSdfModelHere(const std::string& sdf_text, const std::string& source,
                                const PackageResolver& resolver, std::vector<std::string>* warnings,
                                const Limits& limits) {
  checkSize(sdf_text, source, limits);
  std::error_code ec;
  WorldOptions options;
  options.limits = limits;
  WorldSpec spec = parseWith(
      sdf_text,
      [&](sdf::Root& root, const sdf::ParserConfig& config) { return root.LoadSdfString(sdf_text, config); },
      source, fs::absolute(source, ec).parent_path(), resolver, warnings, options, /*model_to_spawn=*/true);
  if (spec.models.empty()) throw SpecError(source, {"no <model> could be read"});
  return std::move(spec.models.front());
}

std::optional<std::string> findWorldFile(const std::string& name, const PackageResolver& resolver,
                                         std::string* error) {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  if (fs::path(name).is_absolute()) {
    candidates.push_back(name);
  } else {
    // Gazebo's resource path first: "worlds/x.world" names a file in one of its folders.
    for (const auto& folder : resolver.gazeboPaths().resourcePath())
      candidates.push_back(fs::path(folder) / name);
    for (const char* package : {"bullet_sim", "bullet_sim_bringup"}) {
      if (const auto dir = resolver.packageDirectory(package)) {
        candidates.push_back(fs::path(*dir) / "worlds" / name);
        candidates.push_back(fs::path(*dir) / name);
      }
    }
    candidates.push_back(fs::absolute(name));
  }
  std::error_code ec;
  for (const auto& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) return candidate.lexically_normal().string();
  }
  if (error) {
    *error = "no world file [" + name + "]; looked at:";
    for (const auto& candidate : candidates) *error += " " + candidate.string();
  }
  return std::nullopt;
}

}  // namespace bullet_sim
