// Triangle meshes loaded with assimp (STL, DAE, OBJ, ...), with the colours and textures their files give,
// from regular files only, within limits.
#pragma once

#include <Eigen/Core>

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/common/limits.h"
#include "bullet_sim/assets/texture.h"

namespace bullet_sim {

/// What a mesh file says a part of the mesh looks like.
struct MeshMaterial {
  std::optional<Eigen::Vector4d> rgba;  ///< diffuse colour and opacity [0, 1]; nullopt: the file gives none
  std::shared_ptr<const Texture> texture;  ///< the diffuse texture; nullptr: none, or it could not be loaded
};

/// A run of a mesh's triangles that share one material.
struct MeshPart {
  int first_triangle = 0;
  int triangle_count = 0;
  int material = 0;  ///< index into TriangleMesh::materials
};

/// How a colour given for a mesh (a visual's) meets the mesh's own materials, as Gazebo applies a <material>.
enum class MeshPaint {
  kOwn,   ///< no colour was given: each part in its file's colour and texture, else in the given colour
  kTint,  ///< a colour was given (URDF <color>, SDF <diffuse>): every part in it, textures multiplied by it
  kUniform,  ///< a Gazebo material script: its colour all over; the mesh's textures are not drawn
};

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;      ///< [m], in the mesh file's frame, scaled
  std::vector<std::array<int, 3>> triangles;  ///< indices into `vertices`
  /// Per vertex, its texture coordinates (u right, v up, (0, 0) at the image's bottom-left corner, as
  /// assimp gives them). Empty when no part has a texture.
  std::vector<Eigen::Vector2f> uvs;
  /// The file's materials; empty when it gives neither colours nor textures (STL).
  std::vector<MeshMaterial> materials;
  /// Cover the triangles in order when `materials` is not empty.
  std::vector<MeshPart> parts;
  /// A closed surface wound counter-clockwise seen from outside (the shapes bullet_sim tessellates): its
  /// triangles' backs never show. Mesh files make no such promise (CAD exports mix windings).
  bool closed = false;
};

/// Loads every mesh of a file into one triangle mesh, with `scale` applied per axis, with its texture
/// coordinates, colours and textures. Textures come through `textures` (each image decoded once); without
/// it, none are loaded. A texture that cannot be found or decoded leaves its part in its colour, with a
/// warning in `warnings`. On failure returns nullopt and sets `error` to a message naming the file and the
/// reason.
///
/// The file, and every file it names (an OBJ's .mtl), must be a regular file (not a FIFO, a device or a
/// directory) of at most limits.max_mesh_bytes. The mesh must have triangles, at most limits.max_triangles,
/// and its scaled vertices must lie within limits.max_length. The importer runs in a child process with
/// bounded memory and limits.mesh_import_seconds of wall time, so a file that crashes or hangs assimp is a
/// load error here, not the end of the simulator.
std::optional<TriangleMesh> loadMesh(const std::string& path, const Eigen::Vector3d& scale,
                                     std::string* error, TextureCache* textures = nullptr,
                                     std::vector<std::string>* warnings = nullptr, const Limits& limits = {});

/// What loadMesh does, done in this process, without a child or a time limit: for the fuzzer.
std::optional<TriangleMesh> importMesh(const std::string& path, const Eigen::Vector3d& scale,
                                       std::string* error, TextureCache* textures = nullptr,
                                       std::vector<std::string>* warnings = nullptr,
                                       const Limits& limits = {});

/// Loads each mesh file once: every visual or collision that names the same file at the same scale shares
/// one TriangleMesh, and every mesh that names the same image shares one Texture.
class MeshCache {
 public:
  explicit MeshCache(const Limits& limits = {}) : limits_(limits) {}
  /// loadMesh, cached; nullptr with `error` set when the file cannot be loaded. Warnings come with the first
  /// load only.
  std::shared_ptr<const TriangleMesh> load(const std::string& path, const Eigen::Vector3d& scale,
                                           std::string* error, std::vector<std::string>* warnings);

 private:
  Limits limits_;
  std::map<std::string, std::shared_ptr<const TriangleMesh>> meshes_;  ///< by path and scale
  TextureCache textures_;
};

}  // namespace bullet_sim
