// Meshes small enough to send to a browser: identical vertices merged, then, above a triangle budget,
// vertices clustered on a grid as coarse as it takes (each cell's vertices become their mean, and triangles
// that collapse are dropped). Coarse, but it keeps a mesh's outline and its parts' order.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <vector>

#include "bullet_sim/assets/mesh.h"

namespace bullet_sim {

struct SimplifiedMesh {
  std::vector<Eigen::Vector3f> vertices;      ///< [m] in the mesh's frame
  std::vector<std::array<int, 3>> triangles;  ///< in the order of the triangles they came from
  std::vector<int> source;                    ///< per triangle, the index of the mesh's triangle it came from
};

/// The mesh with identical vertices merged and, when it has more than `max_triangles` triangles, clustered
/// until it has at most that many (a mesh that cannot get there keeps its coarsest clustering: at least 1).
SimplifiedMesh simplifyMesh(const TriangleMesh& mesh, size_t max_triangles);

}  // namespace bullet_sim
