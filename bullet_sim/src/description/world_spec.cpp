#include "bullet_sim/description/world_spec.h"

#include <stdlib.h>  // mkdtemp
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
#include <sstream>

#include "bullet_sim/description/files.h"
#include "bullet_sim/description/gazebo_materials.h"
#include "bullet_sim/description/mesh.h"
#include "description/world_copies.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

constexpr double kPlaneVisualThickness = 0.001;  // [m] of the box that stands in for a plane visual

struct BuiltinModel {
  const char* uri;
  const char* sdf;
};

// Gazebo classic's ground_plane and sun, as its model database ships them. The sun is a light, not a model.
constexpr BuiltinModel kBuiltinModels[] = {
    {"model://ground_plane", R"(<?xml version="1.0"?>
<sdf version="1.6">
  <model name="ground_plane">
    <static>true</static>
    <link name="link">
      <collision name="collision">
        <geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry>
      </collision>
      <visual name="visual">
        <cast_shadows>false</cast_shadows>
        <geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry>
        <material>
          <script><uri>file://media/materials/scripts/gazebo.material</uri><name>Gazebo/Grey</name></script>
        </material>
      </visual>
    </link>
  </model>
</sdf>
)"},
    {"model://sun", R"(<?xml version="1.0"?>
<sdf version="1.6">
  <light type="directional" name="sun">
    <cast_shadows>true</cast_shadows>
    <pose>0 0 10 0 0 0</pose>
    <diffuse>0.8 0.8 0.8 1</diffuse>
    <specular>0.2 0.2 0.2 1</specular>
    <attenuation><range>1000</range><constant>0.9</constant><linear>0.01</linear><quadratic>0.001</quadratic></attenuation>
    <direction>-0.5 0.1 -0.9</direction>
  </light>
</sdf>
)"},
};

/// A number as SDF would write it: "0.1", not "0.100000".
std::string toText(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

std::string toText(const Eigen::Vector3d& v) {
  return toText(v.x()) + " " + toText(v.y()) + " " + toText(v.z());
}

std::vector<std::string> builtinModelNames() {
  std::vector<std::string> names;
  for (const auto& model : kBuiltinModels) names.push_back(fs::path(model.uri).filename().string());
  return names;
}

/// sdformat resolves an <include> only to a file on disk, so a built-in model is written, when first
/// included, to a private temporary directory that lives as long as one parse.
class BuiltinModelFiles {
 public:
  BuiltinModelFiles() = default;
  BuiltinModelFiles(const BuiltinModelFiles&) = delete;
  BuiltinModelFiles& operator=(const BuiltinModelFiles&) = delete;
  ~BuiltinModelFiles() {
    std::error_code ignored;
    if (!directory_.empty()) fs::remove_all(directory_, ignored);
  }

  static bool isBuiltin(const std::string& uri) { return builtinSdf(uri) != nullptr; }

  /// Path of the file holding the built-in model `uri`; nullopt with `error` set when it cannot be written.
  std::optional<std::string> path(const std::string& uri, std::string* error) {
    if (directory_.empty()) {
      std::string pattern = (fs::temp_directory_path() / "bullet_sim_models_XXXXXX").string();
      if (!mkdtemp(pattern.data())) {
        *error = "cannot create a temporary directory from [" + pattern + "] for the built-in models; set " +
                 "TMPDIR to a writable directory";
        return std::nullopt;
      }
      directory_ = pattern;
    }
    const fs::path file = directory_ / (fs::path(uri).filename().string() + ".sdf");
    if (!fs::exists(file)) {
      std::ofstream out(file);
      out << builtinSdf(uri);
      if (!out) {
        *error = "cannot write the built-in model [" + uri + "] to [" + file.string() +
                 "]; set TMPDIR to a " + "writable directory";
        return std::nullopt;
      }
    }
    return file.string();
  }

 private:
  static const char* builtinSdf(const std::string& uri) {
    for (const auto& model : kBuiltinModels) {
      if (uri == model.uri) return model.sdf;
    }
    return nullptr;
  }

  fs::path directory_;
};

bool hasScheme(const std::string& uri, const std::string& scheme) {
  return uri.rfind(scheme + "://", 0) == 0;
}

/// A path from a package://, file:// or relative URI, relative ones taken from `base_directory`.
/// On failure returns nullopt and sets `error` to the reason and the fix.
std::optional<fs::path> resolveFile(const std::string& uri, const PackageResolver& resolver,
                                    const fs::path& base_directory, std::string* error) {
  if (hasScheme(uri, "model")) {
    const std::string name = uri.substr(std::string("model://").size());
    std::string builtins;
    for (const auto& builtin : builtinModelNames())
      builtins += (builtins.empty() ? "[" : ", [") + builtin + "]";
    *error = "unknown model [" + name + "]" + didYouMean(name, builtinModelNames()) +
             ": bullet_sim has only the built-in models " + builtins +
             "; copy the model into the world file, or refer to it by a package:// URI";
    return std::nullopt;
  }
  if (uri.find("://") != std::string::npos && !hasScheme(uri, "package") && !hasScheme(uri, "file")) {
    *error =
        "unsupported URI scheme in [" + uri + "]; use package://, file:// or a path relative to the SDF file";
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

/// Turns sdformat's DOM of one world into a WorldSpec, collecting every problem in `diagnostics`.
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
      spec.max_step_size = physics->MaxStepSize();
      spec.real_time_factor = physics->RealTimeFactor();
      if (!(spec.max_step_size > 0) || !std::isfinite(spec.max_step_size)) {
        diagnostics_.error(locate(physics->Element()) + "physics [" + physics->Name() + "]: max_step_size [" +
                           toText(spec.max_step_size) + "] must be positive; Gazebo's default is 0.001");
      }
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

 private:
  /// "[file:line] " of an element, for messages.
  std::string locate(const sdf::ElementPtr& element) const {
    return location(element, diagnostics_.source());
  }

  WorldModelSpec toModelSpec(const sdf::Model& model) {
    WorldModelSpec spec;
    spec.name = model.Name();
    spec.pose = resolvePose(model.SemanticPose(), "", "model [" + model.Name() + "]", model.Element());
    spec.is_static = model.Static();
    if (!spec.is_static) {
      diagnostics_.warning(locate(model.Element()) + "model [" + model.Name() +
                           "] is not static: bullet_sim simulates world models as static obstacles; add "
                           "<static>true</static> to it");
    }
    addContents(model, Eigen::Isometry3d::Identity(), model.Name(), spec);
    return spec;
  }

  /// Adds the collisions and visuals of `model` (the top-level model or one nested in it, placed at
  /// `in_top_model`) to `spec`. `scope` is its name for messages, e.g. "house::door".
  void addContents(const sdf::Model& model, const Eigen::Isometry3d& in_top_model, const std::string& scope,
                   WorldModelSpec& spec) {
    if (model.JointCount() > 0) {
      std::string joints;
      for (uint64_t i = 0; i < model.JointCount(); ++i) {
        joints += (i ? ", [" : "[") + model.JointByIndex(i)->Name() + "]";
      }
      diagnostics_.warning(locate(model.Element()) + "model [" + scope + "]: joints " + joints +
                           " ignored: world models are rigid, static obstacles");
    }
    for (const auto& plugin : children(model.Element(), "plugin")) {
      diagnostics_.warning(locate(plugin) + "model [" + scope + "]: plugin [" +
                           plugin->Get<std::string>("name") + "] ignored: world models run no plugins");
    }
    for (uint64_t l = 0; l < model.LinkCount(); ++l) {
      const sdf::Link& link = *model.LinkByIndex(l);
      const std::string owner = "model [" + scope + "] link [" + link.Name() + "]";
      for (uint64_t s = 0; s < link.SensorCount(); ++s) {
        diagnostics_.warning(locate(link.Element()) + owner + ": sensor [" + link.SensorByIndex(s)->Name() +
                             "] ignored: world models have no sensors");
      }
      if (!withinShapeLimit(link.CollisionCount() + link.VisualCount())) return;
      for (uint64_t c = 0; c < link.CollisionCount(); ++c) {
        const sdf::Collision& collision = *link.CollisionByIndex(c);
        const std::string where = owner + " collision [" + collision.Name() + "]";
        std::optional<Shape> shape = toShape(*collision.Geom(), where);
        if (!shape) continue;
        Collision result;
        result.origin =
            in_top_model * resolvePose(collision.SemanticPose(), "__model__", where, collision.Element());
        result.shape = std::move(*shape);
        spec.collisions.push_back(std::move(result));
      }
      for (uint64_t v = 0; v < link.VisualCount(); ++v) {
        const sdf::Visual& visual = *link.VisualByIndex(v);
        const std::string where = owner + " visual [" + visual.Name() + "]";
        std::optional<Shape> shape = toShape(*visual.Geom(), where);
        if (!shape) continue;
        Visual result;
        result.origin =
            in_top_model * resolvePose(visual.SemanticPose(), "__model__", where, visual.Element());
        result.shape = std::move(*shape);
        if (result.shape.type == Shape::Type::kPlane) {
          standInForPlane(*visual.Geom()->PlaneShape(), result);
        }
        applyMaterial(visual, where, result);
        spec.visuals.push_back(std::move(result));
      }
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

  /// False, after one error, once the world's collisions and visuals would pass max_world_shapes.
  bool withinShapeLimit(size_t more) {
    shapes_ += more;
    if (shapes_ <= limits_.max_world_shapes) return true;
    if (!reported_shapes_) {
      diagnostics_.error("the world has more than " + std::to_string(limits_.max_world_shapes) +
                         " collisions and visuals, the limit (max_world_shapes): is it generated by mistake? "
                         "Raise the limit if it is meant");
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
  void applyMaterial(const sdf::Visual& visual, const std::string& where, Visual& result) {
    if (const sdf::Material* material = visual.Material()) {
      const bool has_diffuse = material->Element()->HasElement("diffuse");
      const bool has_ambient = material->Element()->HasElement("ambient");
      const std::string script = material->ScriptName();
      if (!script.empty()) {
        result.material = script;
        if (const std::optional<Eigen::Vector4d> colour = gazeboMaterialColour(script)) {
          result.rgba = *colour;
        } else if (!has_diffuse && !has_ambient) {
          diagnostics_.warning(locate(material->Element()) + where + ": unknown Gazebo material [" + script +
                               "]" + didYouMean(script, gazeboMaterialNames()) +
                               ", shown grey; give it a <diffuse> colour");
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
      diagnostics_.error(at + ": mesh [" + mesh.Uri() + "]: " + error);
      return std::nullopt;
    }
    if (!mesh.Submesh().empty()) {
      diagnostics_.warning(at + ": submesh [" + mesh.Submesh() + "] ignored: the whole mesh is loaded");
    }
    Shape shape;
    shape.type = Shape::Type::kMesh;
    shape.mesh_path = fs::absolute(*path).lexically_normal().string();
    shape.mesh_scale = toEigen(mesh.Scale());
    std::optional<TriangleMesh> triangles = loadMesh(shape.mesh_path, shape.mesh_scale, &error, limits_);
    if (!triangles) {
      diagnostics_.error(at + ": " + error + "; check that the file is an STL, DAE or OBJ mesh");
      return std::nullopt;
    }
    triangles_ += triangles->triangles.size();
    if (triangles_ > limits_.max_triangles) {
      diagnostics_.error(at + ": mesh [" + shape.mesh_path + "] brings the world's meshes to " +
                         std::to_string(triangles_) + " triangles, above the limit of " +
                         std::to_string(limits_.max_triangles) + " (max_triangles): simplify the meshes");
      return std::nullopt;
    }
    shape.mesh = std::make_shared<const TriangleMesh>(std::move(*triangles));
    return shape;
  }

  std::nullopt_t invalidSize(const std::string& what) {
    diagnostics_.error(what + " must be positive; fix the size in the SDF");
    return std::nullopt;
  }

  const PackageResolver& resolver_;
  const fs::path base_directory_;  // for relative paths in SDF text that has no file
  Diagnostics& diagnostics_;
  const Limits& limits_;
  size_t shapes_ = 0;  ///< collisions and visuals so far
  bool reported_shapes_ = false;
  size_t triangles_ = 0;  ///< of every mesh shape so far
};

/// sdformat's errors as ours; it names an unresolved URI and the line of its include, the reason and the fix
/// are ours (`unresolved`: URI -> why).
void reportLoadErrors(const sdf::Errors& errors, std::map<std::string, std::string> unresolved,
                      const std::string& source, Diagnostics& diagnostics) {
  for (const sdf::Error& error : errors) {
    std::string message = describe(error, source);
    for (auto it = unresolved.begin(); it != unresolved.end();) {
      if (error.Message().find("[" + it->first + "]") == std::string::npos) {
        ++it;
        continue;
      }
      message += ": " + it->second;
      it = unresolved.erase(it);
    }
    diagnostics.error(message);
  }
  for (const auto& [uri, reason] : unresolved) diagnostics.error("include [" + uri + "]: " + reason);
}

/// One reading of a world: what it holds, and its problems.
struct Reading {
  WorldSpec spec;
  Diagnostics diagnostics;
};

/// Runs `load` (from a file or from text), or reads `copies->reduced_text` when given, with the built-in
/// models and `resolver` behind <include>, then converts the world. `base_directory` is where relative
/// include and mesh paths start.
Reading readWorld(const WorldCopies* copies,
                  const std::function<sdf::Errors(sdf::Root&, const sdf::ParserConfig&)>& load,
                  const std::string& source, const fs::path& base_directory, const PackageResolver& resolver,
                  const Limits& limits) {
  Reading reading{WorldSpec(), Diagnostics(source)};
  Diagnostics& diagnostics = reading.diagnostics;
  BuiltinModelFiles builtins;
  std::map<std::string, std::string> unresolved;  // include URI -> why it could not be found
  sdf::ParserConfig config;
  config.SetFindCallback([&](const std::string& uri) -> std::string {
    std::string error;
    if (BuiltinModelFiles::isBuiltin(uri)) {
      if (const std::optional<std::string> file = builtins.path(uri, &error)) return *file;
    } else if (const std::optional<fs::path> file = resolveFile(uri, resolver, base_directory, &error)) {
      return file->string();
    }
    unresolved[uri] = error;
    return "";  // sdformat then reports the include as unresolved
  });

  sdf::Root root;
  const sdf::Errors errors = copies ? root.LoadSdfString(copies->reduced_text, config) : load(root, config);
  reportLoadErrors(errors, unresolved, source, diagnostics);
  reading.spec.source = source;
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
  WorldConverter(resolver, base_directory, diagnostics, limits).convert(*root.WorldByIndex(0), reading.spec);
  if (copies) addCopies(*copies, limits, reading.spec, diagnostics);
  return reading;
}

/// Reads a world from `text`, which `load` loads into sdformat (from a file or from the text itself).
WorldSpec parseWith(const std::string& text,
                    const std::function<sdf::Errors(sdf::Root&, const sdf::ParserConfig&)>& load,
                    const std::string& source, const fs::path& base_directory,
                    const PackageResolver& resolver, std::vector<std::string>* warnings,
                    const Limits& limits) {
  // sdformat 12 reports malformed XML only as "Unable to read file" (the detail goes to stderr), so tinyxml2
  // checks it first and names the line and the element.
  tinyxml2::XMLDocument xml;
  if (xml.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS) {
    throw SpecError(source, {"[" + source + ":" + std::to_string(xml.ErrorLineNum()) +
                             "] malformed XML: " + xml.ErrorStr() + "; fix the XML there"});
  }
  // Models that repeat another's contents are read once. Should anything be wrong, the whole file is read
  // again, so that every problem is reported where it is.
  const std::optional<WorldCopies> copies = findCopies(xml);
  Reading reading = readWorld(copies ? &*copies : nullptr, load, source, base_directory, resolver, limits);
  if (copies && !reading.diagnostics.errors().empty())
    reading = readWorld(nullptr, load, source, base_directory, resolver, limits);
  const auto& said = reading.diagnostics.warnings();
  if (warnings) warnings->insert(warnings->end(), said.begin(), said.end());
  reading.diagnostics.throwIfErrors();
  return std::move(reading.spec);
}

}  // namespace

WorldSpec loadWorldHere(const std::string& path, const PackageResolver& resolver,
                        std::vector<std::string>* warnings, const Limits& limits) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw SpecError(path, {"no such file [" + path + "]; check the path (a relative one starts at [" +
                           fs::current_path(ec).string() + "])"});
  }
  std::string text;
  try {
    text = readRegularFile(path, limits.max_description_bytes, "max_description_bytes");
  } catch (const std::runtime_error& e) {
    throw SpecError(path, {std::string("the world file ") + e.what()});
  }
  return parseWith(
      text, [&](sdf::Root& root, const sdf::ParserConfig& config) { return root.Load(path, config); }, path,
      fs::absolute(path, ec).parent_path(), resolver, warnings, limits);
}

WorldSpec parseWorldHere(const std::string& sdf_text, const std::string& source,
                         const PackageResolver& resolver, std::vector<std::string>* warnings,
                         const Limits& limits) {
  std::error_code ec;
  if (sdf_text.size() > limits.max_description_bytes) {
    throw SpecError(source,
                    {"the world is " + std::to_string(sdf_text.size()) + " bytes, above the limit of " +
                     std::to_string(limits.max_description_bytes) + " (max_description_bytes)"});
  }
  return parseWith(
      sdf_text,
      [&](sdf::Root& root, const sdf::ParserConfig& config) { return root.LoadSdfString(sdf_text, config); },
      source, fs::absolute(source, ec).parent_path(), resolver, warnings, limits);
}

std::optional<std::string> findWorldFile(const std::string& name, const PackageResolver& resolver,
                                         std::string* error) {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  if (fs::path(name).is_absolute()) {
    candidates.push_back(name);
  } else {
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
