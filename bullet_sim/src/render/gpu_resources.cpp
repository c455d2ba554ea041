#include "gpu_resources.h"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace bullet_sim {

namespace {

// Faces meeting at less than this angle share their corners' normals (a smooth cylinder); sharper edges
// (a box's) stay sharp.
constexpr double kCreaseAngle = 40 * M_PI / 180;

/// A triangle corner as the vertex buffer holds it: position, normal, texture coordinates.
using Corner = std::array<float, 8>;

struct CornerHash {
  size_t operator()(const Corner& corner) const {
    size_t hash = 0;
    for (const float value : corner) hash = hash * 1000003u ^ std::hash<float>()(value);
    return hash;
  }
};

struct MeshBuffers {
  std::vector<float> vertices;
  std::vector<GLuint> indices;  ///< 3 per triangle, in the mesh's triangle order
};

/// Per triangle corner its position, its normal and, when the mesh has them, its texture coordinates as GL
/// takes them (u, 1 - v: textures are uploaded top row first); equal corners share one vertex. A triangle
/// wound the wrong way (as CAD exports have) gets an inward normal; two-sided lighting lights it right, since
/// the camera then sees its back.
MeshBuffers buffersOf(const TriangleMesh& mesh, int floats_per_vertex) {
  std::vector<Eigen::Vector3d> area_normals, unit_normals;  // per triangle; |area normal| = 2 * area
  std::vector<std::vector<int>> triangles_at(mesh.vertices.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& [a, b, c] = mesh.triangles[t];
    const Eigen::Vector3d normal =
        (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
    area_normals.push_back(normal);
    unit_normals.push_back(normal.norm() > 0 ? normal.normalized() : Eigen::Vector3d::Zero());
    for (const int vertex : mesh.triangles[t]) triangles_at[vertex].push_back(static_cast<int>(t));
  }
  const double crease = std::cos(kCreaseAngle);
  MeshBuffers buffers;
  buffers.indices.reserve(mesh.triangles.size() * 3);
  std::unordered_map<Corner, GLuint, CornerHash> index_of;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const int vertex : mesh.triangles[t]) {
      Eigen::Vector3d smooth = Eigen::Vector3d::Zero();
      for (const int other : triangles_at[vertex]) {
        if (unit_normals[other].dot(unit_normals[t]) >= crease) smooth += area_normals[other];
      }
      const Eigen::Vector3f position = mesh.vertices[vertex].cast<float>();
      const Eigen::Vector3f normal =
          (smooth.norm() > 0 ? smooth.normalized() : unit_normals[t]).cast<float>();
      const Eigen::Vector2f uv = mesh.uvs.empty() ? Eigen::Vector2f::Zero() : mesh.uvs[vertex];
      const Corner corner{position.x(), position.y(), position.z(), normal.x(),
                          normal.y(),   normal.z(),   uv.x(),       1 - uv.y()};
      const auto [found, added] = index_of.try_emplace(corner, static_cast<GLuint>(index_of.size()));
      if (added)
        buffers.vertices.insert(buffers.vertices.end(), corner.begin(), corner.begin() + floats_per_vertex);
      buffers.indices.push_back(found->second);
    }
  }
  return buffers;
}

/// The centre and radius of a sphere around every vertex: around its bounding box's centre.
std::pair<Eigen::Vector3d, double> boundingSphere(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& vertex : mesh.vertices) box.extend(vertex);
  const Eigen::Vector3d centre = box.isEmpty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(box.center());
  double radius = 0;
  for (const Eigen::Vector3d& vertex : mesh.vertices) radius = std::max(radius, (vertex - centre).norm());
  return {centre, radius};
}

/// Deletes the GL objects of entries whose source has expired.
template <class Map, class Delete>
void eraseExpired(Map& map, Delete erase) {
  for (auto it = map.begin(); it != map.end();) {
    if (it->second.source.expired()) {
      erase(it->second);
      it = map.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace

const GpuMesh& GpuResources::mesh(const std::shared_ptr<const TriangleMesh>& mesh) {
  GpuMesh& gpu = meshes_[mesh.get()];
  // A dead mesh's address can be reused by a new one: its weak pointer tells them apart.
  if (gpu.vertices != 0 && gpu.source.lock() == mesh) return gpu;
  if (gpu.vertices == 0) {
    glGenBuffers(1, &gpu.vertices);
    glGenBuffers(1, &gpu.indices);
  }
  gpu.has_uvs = !mesh->uvs.empty();
  const int floats_per_vertex = gpu.has_uvs ? 8 : 6;
  const MeshBuffers buffers = buffersOf(*mesh, floats_per_vertex);
  glBindBuffer(GL_ARRAY_BUFFER, gpu.vertices);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(buffers.vertices.size() * sizeof(float)),
               buffers.vertices.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.indices);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(buffers.indices.size() * sizeof(GLuint)),
               buffers.indices.data(), GL_STATIC_DRAW);
  gpu.source = mesh;
  gpu.stride = static_cast<GLsizei>(floats_per_vertex * sizeof(float));
  std::tie(gpu.centre, gpu.radius) = boundingSphere(*mesh);
  return gpu;
}

GLuint GpuResources::texture(const std::shared_ptr<const Texture>& texture) {
  GpuTexture& gpu = textures_[texture.get()];
  if (gpu.name != 0 && gpu.source.lock() == texture) return gpu.name;
  if (gpu.name == 0) glGenTextures(1, &gpu.name);
  glBindTexture(GL_TEXTURE_2D, gpu.name);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, texture->width, texture->height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               texture->rgba.data());
  // Mipmaps keep far textures from flickering; the nearest level is sampled bilinearly, which llvmpipe does
  // faster than blending two levels.
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  gpu.source = texture;
  return gpu.name;
}

void GpuResources::forgetDead() {
  eraseExpired(meshes_, [](GpuMesh& gpu) {
    glDeleteBuffers(1, &gpu.vertices);
    glDeleteBuffers(1, &gpu.indices);
  });
  eraseExpired(textures_, [](GpuTexture& gpu) { glDeleteTextures(1, &gpu.name); });
}

}  // namespace bullet_sim
