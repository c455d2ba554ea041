// Triangle meshes loaded with assimp (STL, DAE, OBJ, ...), from regular files only, within limits.
#pragma once

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/description/limits.h"

namespace bullet_sim {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;      ///< [m], in the mesh file's frame, scaled
  std::vector<std::array<int, 3>> triangles;  ///< indices into `vertices`
};

/// Loads every mesh of a file into one triangle mesh, with `scale` applied per axis. On failure returns
/// nullopt and sets `error` to a message naming the file and the reason.
///
/// The file, and every file it names (an OBJ's .mtl), must be a regular file (not a FIFO, a device or a
/// directory) of at most limits.max_mesh_bytes. The mesh must have triangles, at most limits.max_triangles,
/// and its scaled vertices must lie within limits.max_length. The importer runs in a child process with
/// bounded memory and limits.mesh_import_seconds of wall time, so a file that crashes or hangs assimp is a
/// load error here, not the end of the simulator.
std::optional<TriangleMesh> loadMesh(const std::string& path, const Eigen::Vector3d& scale,
                                     std::string* error, const Limits& limits = Limits());

/// What loadMesh does in its child process, done in this one, without a time limit: for the fuzzer.
std::optional<TriangleMesh> importMesh(const std::string& path, const Eigen::Vector3d& scale,
                                       std::string* error, const Limits& limits = Limits());

}  // namespace bullet_sim
