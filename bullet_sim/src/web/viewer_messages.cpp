#include "viewer_messages.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "bullet_sim/scene/scene_builder.h"
#include "mesh_simplify.h"

namespace bullet_sim {

namespace {

using Json = nlohmann::json;

constexpr double kPoseUnit = 1e-4;        // [m] positions of poses on the wire
constexpr double kRotationUnit = 1e-5;    // of quaternion components
constexpr double kHitUnit = 1e-3;         // [m]
constexpr double kTimeUnit = 1e-6;        // [s]
constexpr size_t kTextureSamples = 4096;  // pixels averaged for a texture's colour

/// `value` to a whole number of `unit`s (a power of ten below 1), so that it prints short.
double rounded(double value, double unit) { return std::round(value / unit) / std::round(1 / unit); }

Json poseJson(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d p = pose.translation();
  const Eigen::Quaterniond q(pose.rotation());
  return {rounded(p.x(), kPoseUnit),      rounded(p.y(), kPoseUnit),      rounded(p.z(), kPoseUnit),
          rounded(q.x(), kRotationUnit), rounded(q.y(), kRotationUnit), rounded(q.z(), kRotationUnit),
          rounded(q.w(), kRotationUnit)};
}

void appendPose(Json& flat, const Eigen::Isometry3d& pose) {
  for (const auto& value : poseJson(pose)) flat.push_back(value);
}

Eigen::Vector4d meanColour(const Texture& texture) {
  const size_t pixels = texture.rgba.size() / 4;
  if (pixels == 0) return Eigen::Vector4d::Ones();
  const size_t stride = std::max<size_t>(1, pixels / kTextureSamples);
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  size_t count = 0;
  for (size_t p = 0; p < pixels; p += stride, ++count) {
    for (int c = 0; c < 4; ++c) sum[c] += texture.rgba[p * 4 + c] / 255.0;
  }
  return sum / static_cast<double>(count);
}

/// The colour the renderer gives a part of a mesh (offscreen_renderer.cpp's lookOf), a texture as its mean.
Eigen::Vector4d partColour(const ViewerMesh& mesh, const MeshMaterial* material) {
  if (!material || mesh.paint == MeshPaint::kUniform) return mesh.rgba;
  Eigen::Vector4d colour =
      mesh.paint == MeshPaint::kTint
          ? mesh.rgba
          : material->rgba.value_or(material->texture ? Eigen::Vector4d::Ones() : mesh.rgba);
  if (material->texture) colour = colour.cwiseProduct(meanColour(*material->texture));
  return colour;
}

/// A geometry on the wire, and per run of its triangles the mesh material they came from (-1: none).
struct GeometryRuns {
  size_t index = 0;
  std::vector<std::array<int, 3>> runs;  ///< first triangle, count, material
};

/// The material of each of a mesh's triangles, from its parts; -1 where none covers it.
int materialOf(const TriangleMesh& mesh, int triangle) {
  for (const MeshPart& part : mesh.parts) {
    if (triangle >= part.first_triangle && triangle < part.first_triangle + part.triangle_count)
      return part.material;
  }
  return -1;
}

GeometryRuns addGeometry(const TriangleMesh& mesh, size_t max_triangles, Json& geometries) {
  const SimplifiedMesh simple = simplifyMesh(mesh, max_triangles);
  Json positions = Json::array();
  for (const auto& vertex : simple.vertices) {
    for (int axis = 0; axis < 3; ++axis) positions.push_back(std::lround(vertex[axis] / kPositionUnit));
  }
  Json indices = Json::array();
  GeometryRuns geometry{geometries.size(), {}};
  for (size_t t = 0; t < simple.triangles.size(); ++t) {
    for (int corner : simple.triangles[t]) indices.push_back(corner);
    const int material = mesh.materials.empty() ? -1 : materialOf(mesh, simple.source[t]);
    if (geometry.runs.empty() || geometry.runs.back()[2] != material) {
      geometry.runs.push_back({static_cast<int>(t), 0, material});
    }
    ++geometry.runs.back()[1];
  }
  geometries.push_back({{"positions", std::move(positions)}, {"indices", std::move(indices)},
                        {"triangles_in_file", mesh.triangles.size()}});
  return geometry;
}

/// The robot's bodies (its links with visuals, and its root link) and their meshes, into `layout`.
void addRobot(const Robot& robot, ViewerLayout& layout) {
  const ModelSpec& spec = robot.body().spec();
  ViewerRobot entry{robot.name(), layout.bodies.size(), !robot.inputs<Twist>().empty()};
  for (const LinkSpec& link : spec.links) {
    if (link.visuals.empty() && link.name != spec.root) continue;
    if (link.name == spec.root) entry.root_body = layout.bodies.size();
    ViewerBody body;
    body.name = robot.name() + "::" + link.name;
    body.robot = robot.name();
    body.link = link.name;
    body.moves = true;
    body.pose = robot.body().linkPose(link.name);
    for (const Visual& visual : link.visuals) {
      if (visual.shape.type == Shape::Type::kMesh && !visual.shape.mesh) continue;  // not loaded: not drawn
      const SceneMesh mesh = visualMesh(visual, body.pose);
      layout.bounds.extend(meshBounds(mesh));
      layout.meshes.push_back({mesh.mesh, layout.bodies.size(), visual.origin, visual.rgba, visual.paint});
    }
    layout.bodies.push_back(std::move(body));
  }
  layout.robots.push_back(entry);
  for (const auto& [plugin, camera] : robot.sensors<CameraSensor>()) {
    layout.cameras.push_back({robot.name() + "/" + plugin->name(), robot.name(), plugin->name()});
  }
}

}  // namespace

ViewerLayout viewerLayout(const Simulation& simulation, uint64_t revision, size_t max_mesh_triangles) {
  ViewerLayout layout;
  layout.revision = revision;
  layout.max_mesh_triangles = max_mesh_triangles;
  const WorldSpec& world = simulation.world();
  layout.bounds = worldBounds(world);
  for (size_t m = 0; m < world.models.size(); ++m) {
    const WorldModelSpec& model = world.models[m];
    layout.world_model_poses.push_back(simulation.worldModelPose(m));
    for (size_t v = 0; v < model.visuals.size(); ++v) {
      const Visual& visual = model.visuals[v];
      if (visual.shape.type == Shape::Type::kMesh && !visual.shape.mesh) continue;
      ViewerBody body;
      body.name = model.name + "::visual_" + std::to_string(v);
      body.model = m;
      body.visual = v;
      body.moves = !model.is_static;
      body.pose = simulation.worldVisualFrame(m, v);
      layout.meshes.push_back(
          {tessellate(visual.shape), layout.bodies.size(), visual.origin, visual.rgba, visual.paint});
      layout.bodies.push_back(std::move(body));
    }
  }
  for (const std::string& name : simulation.robotNames()) addRobot(*simulation.robot(name), layout);
  return layout;
}

std::string sceneJson(const ViewerLayout& layout) {
  Json bodies = Json::array();
  for (const ViewerBody& body : layout.bodies)
    bodies.push_back({{"name", body.name}, {"pose", poseJson(body.pose)}});
  Json geometries = Json::array();
  Json meshes = Json::array();
  std::map<const TriangleMesh*, GeometryRuns> geometry_of;  // meshes that share a file share a geometry
  for (const ViewerMesh& mesh : layout.meshes) {
    auto geometry = geometry_of.find(mesh.mesh.get());
    if (geometry == geometry_of.end()) {
      geometry =
          geometry_of.emplace(mesh.mesh.get(), addGeometry(*mesh.mesh, layout.max_mesh_triangles, geometries))
              .first;
    }
    Json parts = Json::array();
    for (const auto& [first, count, material] : geometry->second.runs) {
      const Eigen::Vector4d rgba = partColour(mesh, material < 0 ? nullptr : &mesh.mesh->materials[material]);
      parts.push_back({first, count, rounded(rgba[0], 1e-3), rounded(rgba[1], 1e-3), rounded(rgba[2], 1e-3),
                       rounded(rgba[3], 1e-3)});
    }
    meshes.push_back({{"geometry", geometry->second.index},
                      {"body", mesh.body},
                      {"pose", poseJson(mesh.pose)},
                      {"parts", std::move(parts)}});
  }
  Json robots = Json::array();
  for (const ViewerRobot& robot : layout.robots) {
    robots.push_back({{"name", robot.name}, {"body", robot.root_body}, {"teleop", robot.teleop}});
  }
  Json cameras = Json::array();
  for (const ViewerCamera& camera : layout.cameras) cameras.push_back(camera.key);
  Json bounds = nullptr;
  if (!layout.bounds.isEmpty()) {
    const Eigen::Vector3d& low = layout.bounds.min();
    const Eigen::Vector3d& high = layout.bounds.max();
    bounds = {low.x(), low.y(), low.z(), high.x(), high.y(), high.z()};
  }
  return Json{{"type", "scene"},     {"revision", layout.revision}, {"bounds", bounds},
              {"bodies", bodies},    {"geometries", geometries},    {"meshes", meshes},
              {"robots", robots},    {"cameras", cameras}}
      .dump();
}

ViewerFrame viewerFrame(const Simulation& simulation, const ViewerLayout& layout, size_t max_hits) {
  ViewerFrame frame;
  frame.revision = layout.revision;
  frame.time = simulation.time();
  std::vector<bool> moved(layout.world_model_poses.size());
  for (size_t m = 0; m < moved.size(); ++m) {
    moved[m] = simulation.worldModelPose(m).matrix() != layout.world_model_poses[m].matrix();
  }
  std::vector<Eigen::Vector3d> hits;
  std::string robot_name;
  const Robot* robot = nullptr;
  for (size_t b = 0; b < layout.bodies.size(); ++b) {
    const ViewerBody& body = layout.bodies[b];
    if (body.robot.empty()) {
      if (body.moves || moved[body.model])
        frame.poses.emplace_back(b, simulation.worldVisualFrame(body.model, body.visual));
      continue;
    }
    if (body.robot != robot_name) robot = simulation.robot(robot_name = body.robot);
    if (robot) frame.poses.emplace_back(b, robot->body().linkPose(body.link));
  }
  const Eigen::Vector4d red(1, 0, 0, 1);
  for (const std::string& name : simulation.robotNames()) {
    const Robot& each = *simulation.robot(name);
    const auto add = [&](const PointSet& set) {
      hits.insert(hits.end(), set.points.begin(), set.points.end());
    };
    for (const auto& scan : each.outputs<LaserScan>()) {
      if (scan.stream->count() > 0) add(lidarHits(scan.stream->latest(), red, 1));
    }
    for (const auto& cloud : each.outputs<PointCloud>()) {
      if (cloud.stream->count() > 0) add(cloudHits(cloud.stream->latest(), red, 1));
    }
    for (const auto& cloud : each.outputs<LegacyPointCloud>()) {
      if (cloud.stream->count() > 0) add(cloudHits(cloud.stream->latest(), red, 1));
    }
  }
  if (max_hits == 0) return frame;
  const size_t stride = (hits.size() + max_hits - 1) / max_hits;  // 1 while they fit
  for (size_t i = 0; i < hits.size(); i += stride) frame.hits.push_back(hits[i].cast<float>());
  return frame;
}

std::string frameJson(const ViewerFrame& frame) {
  Json poses = Json::array();
  for (const auto& [body, pose] : frame.poses) {
    poses.push_back(body);
    appendPose(poses, pose);
  }
  Json hits = Json::array();
  for (const auto& hit : frame.hits) {
    for (int axis = 0; axis < 3; ++axis) hits.push_back(rounded(hit[axis], kHitUnit));
  }
  return Json{{"type", "frame"},
              {"revision", frame.revision},
              {"time", rounded(frame.time, kTimeUnit)},
              {"rtf", rounded(frame.rtf, 1e-3)},
              {"paused", frame.paused},
              {"poses", std::move(poses)},
              {"hits", std::move(hits)}}
      .dump();
}

std::string imageMessage(const std::string& camera, const CameraImage& image) {
  const std::string header = Json{
      {"type", "image"},        {"camera", camera},           {"width", image.width},
      {"height", image.height}, {"encoding", image.encoding}, {"step", image.step},
      {"stamp", image.stamp}}.dump();
  std::string message;
  message.reserve(4 + header.size() + image.data.size());
  const auto length = static_cast<uint32_t>(header.size());
  for (int byte = 0; byte < 4; ++byte) message.push_back(static_cast<char>((length >> (8 * byte)) & 0xff));
  message += header;
  message.append(reinterpret_cast<const char*>(image.data.data()), image.data.size());
  return message;
}

const Stream<CameraImage>* cameraStream(const Simulation& simulation, const ViewerCamera& camera) {
  const Robot* robot = simulation.robot(camera.robot);
  if (!robot) return nullptr;
  for (const auto& output : robot->outputs<CameraImage>()) {
    if (output.plugin->name() == camera.sensor) return output.stream;
  }
  return nullptr;
}

void wantCamera(const Simulation& simulation, const ViewerCamera& camera) {
  const Robot* robot = simulation.robot(camera.robot);
  if (!robot) return;
  for (const auto& plugin : robot->plugins()) {
    if (plugin->name() != camera.sensor) continue;
    for (const OutputPort& port : plugin->ports().outputs) {
      if (std::holds_alternative<const Stream<CameraImage>*>(port.stream) && port.demand) {
        port.demand->wanted = true;
        return;  // its first image: the colour one
      }
    }
  }
}

namespace {

class SceneOutgoing final : public Outgoing {
 public:
  explicit SceneOutgoing(std::shared_ptr<const ViewerLayout> layout)
      : Outgoing(false), layout_(std::move(layout)) {}

 private:
  std::string serialise() const override { return sceneJson(*layout_); }
  std::shared_ptr<const ViewerLayout> layout_;
};

class FrameOutgoing final : public Outgoing {
 public:
  explicit FrameOutgoing(ViewerFrame frame) : Outgoing(false), frame_(std::move(frame)) {}

 private:
  std::string serialise() const override { return frameJson(frame_); }
  ViewerFrame frame_;
};

class ImageOutgoing final : public Outgoing {
 public:
  ImageOutgoing(std::string camera, CameraImage image)
      : Outgoing(true), camera_(std::move(camera)), image_(std::move(image)) {}

 private:
  std::string serialise() const override { return imageMessage(camera_, image_); }
  std::string camera_;
  CameraImage image_;
};

}  // namespace

std::shared_ptr<const Outgoing> sceneMessage(std::shared_ptr<const ViewerLayout> layout) {
  return std::make_shared<SceneOutgoing>(std::move(layout));
}

std::shared_ptr<const Outgoing> frameMessage(ViewerFrame frame) {
  return std::make_shared<FrameOutgoing>(std::move(frame));
}

std::shared_ptr<const Outgoing> imageOutgoing(std::string camera, CameraImage image) {
  return std::make_shared<ImageOutgoing>(std::move(camera), std::move(image));
}

}  // namespace bullet_sim
