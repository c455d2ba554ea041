// Fills a Scene from what the simulator knows: a robot's visuals at its link poses, a world's visuals, lidar
// hits. ROS-free and Bullet-free: it reads the spec structs only.
#pragma once

#include <Eigen/Geometry>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/model/geometry.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/model/world.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/scene/scene.h"

namespace bullet_sim {

/// The triangles of a shape in its own frame: a box centred on the origin, a cylinder along z centred on the
/// origin, a sphere, a plane as a 100 m square (Gazebo's ground size) through the origin, a mesh as loaded.
/// Throws std::invalid_argument for a mesh shape whose mesh was not loaded.
std::shared_ptr<const TriangleMesh> tessellate(const Shape& shape);

/// A visual in its colour, placed in `frame` (its link's or model's pose in the world).
SceneMesh visualMesh(const Visual& visual, const Eigen::Isometry3d& frame);

/// Adds every visual of `model` in its colour, each link at its world pose in `link_poses`, and returns the
/// world bounds of what it added (empty for a model without visuals). Throws std::invalid_argument naming the
/// link when a link with visuals has no pose.
Eigen::AlignedBox3d addModel(Scene& scene, const ModelSpec& model,
                             const std::map<std::string, Eigen::Isometry3d>& link_poses);

/// Adds every visual of the world's models, the ground plane included, where the world file puts them.
void addWorld(Scene& scene, const WorldSpec& world);

/// Where the beams of a scan hit, in the world: one point per finite range (not +inf, no return, nor -inf,
/// closer than range_min), placed with the scan's sensor_pose.
PointSet lidarHits(const LaserScan& scan, const Eigen::Vector4d& rgba, double size);

/// The points of a lidar's point cloud, in the world.
PointSet cloudHits(const PointCloud& cloud, const Eigen::Vector4d& rgba, double size);

/// The world bounds of a world's obstacles: every collision but infinite planes, so that the ground does not
/// make every plan 100 m wide. Empty for a world with nothing but the ground.
Eigen::AlignedBox3d worldBounds(const WorldSpec& world);

/// The world bounds of a mesh at its pose.
Eigen::AlignedBox3d meshBounds(const SceneMesh& mesh);

}  // namespace bullet_sim
