#include "bullet_sim/description/mesh.h"

#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <sstream>

namespace bullet_sim {

namespace fs = std::filesystem;

namespace {

/// Where Gazebo looks for a texture a mesh names: beside the mesh, then in the model's materials/textures
/// (common/Material.cc); an absolute path as it is. "file://" prefixes are dropped.
std::vector<fs::path> textureCandidates(const std::string& mesh_path, std::string name) {
  if (name.rfind("file://", 0) == 0) name.erase(0, 7);
  if (fs::path(name).is_absolute()) return {name};
  const fs::path directory = fs::path(mesh_path).parent_path();
  return {directory / name, directory / ".." / "materials" / "textures" / name};
}

/// An image embedded in the mesh file (glTF, FBX): compressed bytes, or raw BGRA texels.
std::shared_ptr<const Texture> embeddedTexture(const aiTexture& embedded, const std::string& source,
                                               TextureCache& textures, std::string* error) {
  if (embedded.mHeight == 0) {  // mWidth bytes of a PNG or JPEG file
    return textures.decode(reinterpret_cast<const uint8_t*>(embedded.pcData), embedded.mWidth, source, error);
  }
  const int64_t pixels = static_cast<int64_t>(embedded.mWidth) * embedded.mHeight;
  if (pixels > TextureLimits{}.max_pixels) {
    *error = "image [" + source + "] of " + std::to_string(embedded.mWidth) + " x " +
             std::to_string(embedded.mHeight) + " px is larger than bullet_sim draws";
    return nullptr;
  }
  Texture texture;
  texture.width = static_cast<int>(embedded.mWidth);
  texture.height = static_cast<int>(embedded.mHeight);
  texture.source = source;
  texture.rgba.reserve(static_cast<size_t>(pixels) * 4);
  for (int64_t i = 0; i < pixels; ++i) {
    const aiTexel& texel = embedded.pcData[i];
    texture.rgba.insert(texture.rgba.end(), {texel.r, texel.g, texel.b, texel.a});
  }
  return textures.adopt(std::move(texture), error);
}

/// The diffuse (or glTF base colour) texture a material names, loaded; nullptr, with a warning when it names
/// one that cannot be loaded.
std::shared_ptr<const Texture> diffuseTexture(const aiScene& scene, const aiMaterial& material,
                                              const std::string& mesh_path, TextureCache& textures,
                                              std::vector<std::string>* warnings) {
  aiString name;
  if (material.GetTexture(aiTextureType_DIFFUSE, 0, &name) != AI_SUCCESS &&
      material.GetTexture(aiTextureType_BASE_COLOR, 0, &name) != AI_SUCCESS) {
    return nullptr;
  }
  std::string error;
  std::shared_ptr<const Texture> texture;
  if (const aiTexture* embedded = scene.GetEmbeddedTexture(name.C_Str())) {
    texture = embeddedTexture(*embedded, mesh_path + " " + name.C_Str(), textures, &error);
  } else {
    const std::vector<fs::path> candidates = textureCandidates(mesh_path, name.C_Str());
    std::error_code ec;
    const auto found = std::find_if(candidates.begin(), candidates.end(),
                                    [&](const fs::path& candidate) { return fs::exists(candidate, ec); });
    if (found != candidates.end()) {
      texture = textures.load(found->lexically_normal().string(), &error);
    } else {
      error = "texture [" + std::string(name.C_Str()) + "] not found; looked for";
      for (const fs::path& candidate : candidates)
        error += " [" + candidate.lexically_normal().string() + "]";
    }
  }
  if (!texture && warnings) {
    warnings->push_back("mesh [" + mesh_path + "]: " + error + "; that part is drawn in its material colour");
  }
  return texture;
}

/// The file's materials, by assimp's index; empty when none gives a colour or a texture. assimp's stand-in
/// for files without materials (STL) gives none.
std::vector<MeshMaterial> readMaterials(const aiScene& scene, const std::string& mesh_path,
                                        TextureCache* textures, std::vector<std::string>* warnings) {
  std::vector<MeshMaterial> materials(scene.mNumMaterials);
  bool any = false;
  for (unsigned m = 0; m < scene.mNumMaterials; ++m) {
    const aiMaterial& material = *scene.mMaterials[m];
    aiString name;
    if (material.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name == aiString(AI_DEFAULT_MATERIAL_NAME))
      continue;
    aiColor4D colour;
    if (material.Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS ||
        material.Get(AI_MATKEY_BASE_COLOR, colour) == AI_SUCCESS) {
      float opacity = 1;
      material.Get(AI_MATKEY_OPACITY, opacity);
      materials[m].rgba = Eigen::Vector4d(colour.r, colour.g, colour.b, colour.a * opacity);
    }
    if (textures) materials[m].texture = diffuseTexture(scene, material, mesh_path, *textures, warnings);
    any = any || materials[m].rgba || materials[m].texture;
  }
  if (!any) materials.clear();
  return materials;
}

/// Appends one assimp mesh, placed by `transform` and scaled, to `mesh`: its vertices, texture coordinates
/// (when `with_uvs`), triangles and, when the file has materials, its part.
void appendMesh(const aiMesh& sub, const aiMatrix4x4& transform, const Eigen::Vector3d& scale, bool with_uvs,
                TriangleMesh& mesh) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (unsigned v = 0; v < sub.mNumVertices; ++v) {
    const aiVector3D p = transform * sub.mVertices[v];
    mesh.vertices.emplace_back(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
    if (!with_uvs) continue;
    const aiVector3D uv = sub.HasTextureCoords(0) ? sub.mTextureCoords[0][v] : aiVector3D();
    mesh.uvs.emplace_back(uv.x, uv.y);
  }
  const int first = static_cast<int>(mesh.triangles.size());
  for (unsigned f = 0; f < sub.mNumFaces; ++f) {
    const aiFace& face = sub.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines carry no surface
    mesh.triangles.push_back({base + static_cast<int>(face.mIndices[0]),
                              base + static_cast<int>(face.mIndices[1]),
                              base + static_cast<int>(face.mIndices[2])});
  }
  const int count = static_cast<int>(mesh.triangles.size()) - first;
  if (mesh.materials.empty() || count == 0) return;
  const int material = static_cast<int>(sub.mMaterialIndex);
  if (!mesh.parts.empty() && mesh.parts.back().material == material) {
    mesh.parts.back().triangle_count += count;
  } else {
    mesh.parts.push_back({first, count, material});
  }
}

}  // namespace

std::optional<TriangleMesh> loadMesh(const std::string& path, const Eigen::Vector3d& scale,
                                     std::string* error, TextureCache* textures,
                                     std::vector<std::string>* warnings) {
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
  mesh.materials = readMaterials(*scene, path, textures, warnings);
  const bool with_uvs = std::any_of(mesh.materials.begin(), mesh.materials.end(),
                                    [](const MeshMaterial& material) { return material.texture != nullptr; });
  // Node transforms place each sub-mesh (DAE and OBJ files nest them); STL has just the root.
  std::function<void(const aiNode*, const aiMatrix4x4&)> visit = [&](const aiNode* node,
                                                                     const aiMatrix4x4& parent) {
    const aiMatrix4x4 transform = parent * node->mTransformation;
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      appendMesh(*scene->mMeshes[node->mMeshes[m]], transform, scale, with_uvs, mesh);
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

std::shared_ptr<const TriangleMesh> MeshCache::load(const std::string& path, const Eigen::Vector3d& scale,
                                                    std::string* error, std::vector<std::string>* warnings) {
  std::ostringstream key;
  key << path << '|' << scale.transpose();
  std::shared_ptr<const TriangleMesh>& cached = meshes_[key.str()];
  if (!cached) {
    if (std::optional<TriangleMesh> mesh = loadMesh(path, scale, error, &textures_, warnings)) {
      cached = std::make_shared<const TriangleMesh>(std::move(*mesh));
    }
  }
  return cached;
}

}  // namespace bullet_sim
