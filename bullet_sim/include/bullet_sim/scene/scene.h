// What the offscreen renderer draws: plain meshes, points and lines in the world frame [m], a camera and a
// light. No Bullet and no ROS: scene_builder.h fills it from model and world specs and from lidar scans.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <vector>

#include "bullet_sim/assets/mesh.h"
#include "bullet_sim/scene/camera.h"

namespace bullet_sim {

struct SceneMesh {
  /// Triangles in the mesh's own frame [m], with the colours and textures of its file. The renderer keeps its
  /// copy (and its textures') on the GPU while this stays alive, so sharing one mesh across scenes and
  /// renders uploads it once.
  std::shared_ptr<const TriangleMesh> mesh;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the mesh frame in the world
  Eigen::Vector4d rgba{0.7, 0.7, 0.7, 1};                  ///< [0, 1]; alpha < 1 is drawn see-through
  MeshPaint paint = MeshPaint::kOwn;  ///< how rgba meets the mesh's own colours and textures
};

/// Square dots of one colour, unlit.
struct PointSet {
  std::vector<Eigen::Vector3d> points;  ///< world [m]
  Eigen::Vector4d rgba{1, 0, 0, 1};
  double size = 4;  ///< side [px]
  /// Drawn over every mesh (e.g. lidar hits under a table top in a plan); otherwise nearer meshes hide them.
  bool overlay = false;
};

/// A connected line through its points (e.g. an odometry trail), unlit; nearer meshes hide it.
struct Polyline {
  std::vector<Eigen::Vector3d> points;  ///< world [m]
  Eigen::Vector4d rgba{0, 0.6, 0, 1};
  double width = 2;  ///< [px]
};

/// One directional light plus ambient light, as OpenGL's fixed-function lighting computes them per vertex.
struct Lighting {
  /// The way the light travels, in the world (normalised when used): from above, behind the left shoulder of
  /// a camera that looks along +x, so that a chase view of a robot spawned facing +x sees its lit side.
  Eigen::Vector3d direction{0.4, -0.3, -1};
  double ambient = 0.45;  ///< share of a surface's colour that it shows facing away from the light
  double diffuse = 0.55;  ///< added share, times the cosine between the normal and the way to the light

  /// The RGB [0, 1] that a surface of colour `rgba` gets where its normal is `normal` (world, towards the
  /// camera): rgb * (ambient + diffuse * max(0, cos)), clamped to 1.
  Eigen::Vector3d shade(const Eigen::Vector4d& rgba, const Eigen::Vector3d& normal) const;
};

struct Scene {
  std::vector<SceneMesh> meshes;
  std::vector<PointSet> point_sets;
  std::vector<Polyline> polylines;
  /// Lines every metre on z = 0 around what the camera looks at (Scene::kGridHalfExtent to each side).
  bool ground_grid = true;
  Eigen::Vector4d background{0.78, 0.84, 0.9, 1};  ///< sky
  Eigen::Vector4d grid_rgba{0.35, 0.35, 0.35, 1};
  Lighting lighting;
  Camera camera;
  /// [m] Surfaces get a dark outline where what lies beside them is this much farther from the camera (0:
  /// none). A plan view needs it: a robot's seat lit from above is the floor's colour when both are grey.
  double outline_step = 0;
  Eigen::Vector4d outline_rgba{0.15, 0.15, 0.15, 1};

  static constexpr double kGridSpacing = 1;      ///< [m]
  static constexpr double kGridHalfExtent = 20;  ///< [m]
};

}  // namespace bullet_sim
