// Shapes, collisions and visuals shared by robot and world specs.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/assets/mesh.h"

namespace bullet_sim {

/// A mesh split into convex parts, so that a moving body collides by shapes close to its mesh.
struct ConvexParts {
  std::vector<std::vector<Eigen::Vector3d>> hulls;  ///< per part, its hull's points [m], in the mesh's frame
};

struct Shape {
  enum class Type { kBox, kCylinder, kSphere, kMesh, kPlane };
  Type type = Type::kBox;
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();       ///< kBox: full extents [m]
  double radius = 0;                                        ///< kCylinder (along local z), kSphere [m]
  double length = 0;                                        ///< kCylinder [m]
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitZ();  ///< kPlane: infinite plane through the origin
  std::string mesh_path;                                    ///< kMesh: resolved absolute path
  Eigen::Vector3d mesh_scale = Eigen::Vector3d::Ones();
  std::shared_ptr<const TriangleMesh> mesh;  ///< kMesh: loaded, scale applied
  /// kMesh of a moving link's collision: its convex parts (ConvexDecomposer); null: it collides by its hull
  /// (by its triangles on a link fixed to the world or a static model).
  std::shared_ptr<const ConvexParts> convex_parts;
};

struct Collision {
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< in the owning link's or model's frame
  Shape shape;
  /// A URDF collision's name attribute ("" when it has none); a world's collision's scoped Gazebo name,
  /// model::link::collision.
  std::string name;
  /// A world collision's <surface><friction><ode><mu> (Gazebo's default 1); a robot's links carry theirs.
  double mu = 1.0;
};

struct Visual {
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Shape shape;
  Eigen::Vector4d rgba{0.7, 0.7, 0.7, 1.0};
  std::string material;  ///< e.g. "Gazebo/Gray" when the colour came from a Gazebo material name
  MeshPaint paint = MeshPaint::kOwn;  ///< how `rgba` meets a mesh's own colours and textures
};

}  // namespace bullet_sim
