// What the offscreen renderer keeps in its OpenGL context between renders: each mesh's vertex and index
// buffers and each texture, uploaded when first drawn and deleted once nothing holds its source any more.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES
#endif
#include <GL/gl.h>
#include <GL/glext.h>

#include <Eigen/Core>

#include <memory>
#include <unordered_map>

#include "bullet_sim/scene/scene.h"

namespace bullet_sim {

struct GpuMesh {
  std::weak_ptr<const TriangleMesh> source;  ///< expired once nobody draws it any more
  GLuint vertices = 0;                       ///< buffer of per-vertex attributes (see stride)
  GLuint indices = 0;                        ///< buffer of 3 GLuint vertex indices per triangle
  GLsizei stride = 0;                        ///< [bytes]: position, normal, then texture coordinates if any
  bool has_uvs = false;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< of a sphere around the mesh, in its frame [m]
  double radius = 0;                                 ///< [m]
};

class GpuResources {
 public:
  GpuResources() = default;
  GpuResources(const GpuResources&) = delete;
  GpuResources& operator=(const GpuResources&) = delete;

  /// The mesh's buffers, uploaded on first use. Call with the context current.
  const GpuMesh& mesh(const std::shared_ptr<const TriangleMesh>& mesh);
  /// The texture's name, uploaded (with its mipmaps) on first use.
  GLuint texture(const std::shared_ptr<const Texture>& texture);
  /// Deletes what belongs to meshes and textures that no longer exist.
  void forgetDead();

 private:
  struct GpuTexture {
    std::weak_ptr<const Texture> source;
    GLuint name = 0;
  };
  std::unordered_map<const TriangleMesh*, GpuMesh> meshes_;
  std::unordered_map<const Texture*, GpuTexture> textures_;
};

}  // namespace bullet_sim
