// Triangle meshes loaded with assimp (STL, DAE, OBJ, ...).
#pragma once

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;      ///< [m], in the mesh file's frame, scaled
  std::vector<std::array<int, 3>> triangles;  ///< indices into `vertices`
};

/// Loads every mesh of a file into one triangle mesh, with `scale` applied per axis.
/// On failure returns nullopt and sets `error` to a message naming the file and the reason.
std::optional<TriangleMesh> loadMesh(const std::string& path, const Eigen::Vector3d& scale,
                                     std::string* error);

}  // namespace bullet_sim
