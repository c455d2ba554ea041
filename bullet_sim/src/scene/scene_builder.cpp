#include "bullet_sim/scene/scene_builder.h"

#include <cmath>
#include <stdexcept>

namespace bullet_sim {

namespace {

constexpr int kRoundSegments = 32;      // around a cylinder or a sphere: smooth enough at 640 x 480
constexpr int kSphereRings = 16;        // pole to pole
constexpr double kPlaneQuadSize = 100;  // [m], Gazebo's default <plane><size>

using Triangle = std::array<int, 3>;

TriangleMesh box(const Eigen::Vector3d& size) {
  TriangleMesh mesh;
  for (int corner = 0; corner < 8; ++corner) {
    mesh.vertices.emplace_back((corner & 1 ? 0.5 : -0.5) * size.x(), (corner & 2 ? 0.5 : -0.5) * size.y(),
                               (corner & 4 ? 0.5 : -0.5) * size.z());
  }
  // Counter-clockwise seen from outside; corner bits are x = 1, y = 2, z = 4.
  mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return mesh;
}

TriangleMesh cylinder(double radius, double length) {
  TriangleMesh mesh;
  for (const double z : {-length / 2, length / 2}) {
    for (int i = 0; i < kRoundSegments; ++i) {
      const double angle = 2 * M_PI * i / kRoundSegments;
      mesh.vertices.emplace_back(radius * std::cos(angle), radius * std::sin(angle), z);
    }
  }
  const int bottom_centre = static_cast<int>(mesh.vertices.size());
  mesh.vertices.emplace_back(0, 0, -length / 2);
  mesh.vertices.emplace_back(0, 0, length / 2);
  const int top_centre = bottom_centre + 1;
  for (int i = 0; i < kRoundSegments; ++i) {
    const int next = (i + 1) % kRoundSegments;
    const int top = kRoundSegments;
    mesh.triangles.push_back({i, next, top + next});
    mesh.triangles.push_back({i, top + next, top + i});
    mesh.triangles.push_back({top_centre, top + i, top + next});
    mesh.triangles.push_back({bottom_centre, next, i});
  }
  return mesh;
}

TriangleMesh sphere(double radius) {
  TriangleMesh mesh;
  mesh.vertices.emplace_back(0, 0, -radius);
  for (int ring = 1; ring < kSphereRings; ++ring) {
    const double polar = M_PI * ring / kSphereRings;  // from the south pole
    for (int i = 0; i < kRoundSegments; ++i) {
      const double angle = 2 * M_PI * i / kRoundSegments;
      mesh.vertices.emplace_back(radius * std::sin(polar) * std::cos(angle),
                                 radius * std::sin(polar) * std::sin(angle), -radius * std::cos(polar));
    }
  }
  mesh.vertices.emplace_back(0, 0, radius);
  const int north = static_cast<int>(mesh.vertices.size()) - 1;
  const auto at = [](int ring, int i) { return 1 + (ring - 1) * kRoundSegments + i % kRoundSegments; };
  for (int i = 0; i < kRoundSegments; ++i) {
    mesh.triangles.push_back({0, at(1, i + 1), at(1, i)});
    mesh.triangles.push_back({north, at(kSphereRings - 1, i), at(kSphereRings - 1, i + 1)});
    for (int ring = 1; ring + 1 < kSphereRings; ++ring) {
      mesh.triangles.push_back({at(ring, i), at(ring, i + 1), at(ring + 1, i + 1)});
      mesh.triangles.push_back({at(ring, i), at(ring + 1, i + 1), at(ring + 1, i)});
    }
  }
  return mesh;
}

TriangleMesh plane(const Eigen::Vector3d& normal) {
  const Eigen::Matrix3d rotation =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal).toRotationMatrix();
  TriangleMesh mesh;
  for (const auto& corner : {Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, -1, 0), Eigen::Vector3d(1, 1, 0),
                             Eigen::Vector3d(-1, 1, 0)}) {
    mesh.vertices.push_back(rotation * corner * kPlaneQuadSize / 2);
  }
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

/// A closed shape: its back faces never show.
std::shared_ptr<const TriangleMesh> closed(TriangleMesh mesh) {
  mesh.closed = true;
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

}  // namespace

std::shared_ptr<const TriangleMesh> tessellate(const Shape& shape) {
  switch (shape.type) {
    case Shape::Type::kBox:
      return closed(box(shape.box_size));
    case Shape::Type::kCylinder:
      return closed(cylinder(shape.radius, shape.length));
    case Shape::Type::kSphere:
      return closed(sphere(shape.radius));
    case Shape::Type::kPlane:
      return std::make_shared<const TriangleMesh>(plane(shape.plane_normal));
    case Shape::Type::kMesh:
      if (!shape.mesh) {
        throw std::invalid_argument("mesh [" + shape.mesh_path +
                                    "] was not loaded: build shapes with parseModel or loadWorld");
      }
      return shape.mesh;
  }
  throw std::invalid_argument("unknown shape type");
}

SceneMesh visualMesh(const Visual& visual, const Eigen::Isometry3d& frame) {
  return {tessellate(visual.shape), frame * visual.origin, visual.rgba, visual.paint};
}

Eigen::AlignedBox3d addModel(Scene& scene, const ModelSpec& model,
                             const std::map<std::string, Eigen::Isometry3d>& link_poses) {
  Eigen::AlignedBox3d bounds;
  for (const LinkSpec& link : model.links) {
    if (link.visuals.empty()) continue;
    const auto pose = link_poses.find(link.name);
    if (pose == link_poses.end()) {
      throw std::invalid_argument("addModel: no pose for link [" + link.name + "] of model [" + model.name +
                                  "]; pass the world pose of every link that has visuals");
    }
    for (const Visual& visual : link.visuals) {
      scene.meshes.push_back(visualMesh(visual, pose->second));
      bounds.extend(meshBounds(scene.meshes.back()));
    }
  }
  return bounds;
}

void addWorld(Scene& scene, const WorldSpec& world) {
  for (const WorldModelSpec& model : world.models) {
    for (const Visual& visual : model.visuals) scene.meshes.push_back(visualMesh(visual, model.pose));
  }
}

PointSet lidarHits(const LaserScan& scan, const Eigen::Vector4d& rgba, double size) {
  PointSet hits;
  hits.rgba = rgba;
  hits.size = size;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double range = scan.ranges[i];
    if (!std::isfinite(range)) continue;
    const double angle = scan.angle_min + static_cast<double>(i) * scan.angle_increment;
    hits.points.push_back(scan.sensor_pose *
                          Eigen::Vector3d(range * std::cos(angle), range * std::sin(angle), 0));
  }
  return hits;
}

PointSet cloudHits(const PointCloud& cloud, const Eigen::Vector4d& rgba, double size) {
  PointSet hits;
  hits.rgba = rgba;
  hits.size = size;
  hits.points.reserve(cloud.points.size());
  for (const auto& point : cloud.points) hits.points.push_back(cloud.sensor_pose * point.cast<double>());
  return hits;
}

Eigen::AlignedBox3d worldBounds(const WorldSpec& world) {
  Eigen::AlignedBox3d bounds;
  for (const WorldModelSpec& model : world.models) {
    for (const Collision& collision : model.collisions) {
      if (collision.shape.type == Shape::Type::kPlane) continue;
      bounds.extend(meshBounds({tessellate(collision.shape), model.pose * collision.origin}));
    }
  }
  return bounds;
}

Eigen::AlignedBox3d meshBounds(const SceneMesh& mesh) {
  Eigen::AlignedBox3d bounds;
  for (const Eigen::Vector3d& vertex : mesh.mesh->vertices) bounds.extend(mesh.pose * vertex);
  return bounds;
}

}  // namespace bullet_sim
