#include "bullet_sim/description/mesh.h"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <functional>

namespace bullet_sim {

std::optional<TriangleMesh> loadMesh(const std::string& path, const Eigen::Vector3d& scale,
                                     std::string* error) {
  Assimp::Importer importer;
  // COLLADA as RViz, Gazebo, FCL and MoveIt read it: the vertices in the file's axes, scaled by its <unit
  // meter>, without assimp's turn of a Z_UP file into Y_UP (which stood a Z_UP jersey barrier on its end).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) {
    if (error) *error = "cannot load mesh [" + path + "]: " + importer.GetErrorString();
    return std::nullopt;
  }

  TriangleMesh mesh;
  // Node transforms place each sub-mesh (DAE and OBJ files nest them); STL has just the root.
  std::function<void(const aiNode*, const aiMatrix4x4&)> visit = [&](const aiNode* node,
                                                                     const aiMatrix4x4& parent) {
    const aiMatrix4x4 transform = parent * node->mTransformation;
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const aiMesh* sub = scene->mMeshes[node->mMeshes[m]];
      const int base = static_cast<int>(mesh.vertices.size());
      for (unsigned v = 0; v < sub->mNumVertices; ++v) {
        const aiVector3D p = transform * sub->mVertices[v];
        mesh.vertices.emplace_back(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
      }
      for (unsigned f = 0; f < sub->mNumFaces; ++f) {
        const aiFace& face = sub->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines carry no surface
        mesh.triangles.push_back({base + static_cast<int>(face.mIndices[0]),
                                  base + static_cast<int>(face.mIndices[1]),
                                  base + static_cast<int>(face.mIndices[2])});
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) visit(node->mChildren[c], transform);
  };
  visit(scene->mRootNode, aiMatrix4x4());

  if (mesh.triangles.empty()) {
    if (error) *error = "mesh [" + path + "] has no triangles";
    return std::nullopt;
  }
  return mesh;
}

}  // namespace bullet_sim
