#include "bullet_sim/assets/mesh.h"

#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/DefaultIOStream.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "bullet_sim/common/files.h"
#include "assets/byte_codec.h"
#include "assets/child_process.h"
#include "assets/mesh_fields.h"

namespace bullet_sim {

namespace fs = std::filesystem;

namespace {

// What a child may map beyond its parent to import one file: assimp's structures take several times the
// file's size.
constexpr size_t kImportMemoryBase = size_t{2} << 30;  // [bytes]
constexpr size_t kImportMemoryPerFileByte = 24;

/// A file stream of assimp's own kind, over a file opened here.
class CheckedStream : public Assimp::DefaultIOStream {
 public:
  CheckedStream(FILE* file, const std::string& name) : Assimp::DefaultIOStream(file, name) {}
};

/// assimp's file system, opening only regular files of at most max_mesh_bytes: an OBJ may name a FIFO or
/// /dev/zero as its .mtl. It opens without blocking and checks what it opened, so nothing can swap the file.
class RegularFileSystem : public Assimp::DefaultIOSystem {
 public:
  RegularFileSystem(size_t max_bytes, std::string* problem) : max_bytes_(max_bytes), problem_(problem) {}

  /// Without opening it: assimp's own Exists opens the file, and blocks on a FIFO.
  bool Exists(const char* path) const override {
    struct stat status {};
    return stat(path, &status) == 0;
  }

  Assimp::IOStream* Open(const char* path, const char* mode) override {
    if (std::strchr(mode, 'w') || std::strchr(mode, 'a') || std::strchr(mode, '+')) return nullptr;
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return nullptr;  // assimp says that it cannot open it
    const std::optional<std::string> problem = openedFileProblem(fd, max_bytes_, "max_mesh_bytes");
    FILE* file = problem ? nullptr : fdopen(fd, "rb");
    if (!file) {
      if (problem_->empty()) *problem_ = "[" + std::string(path) + "] " + problem.value_or("cannot be read");
      close(fd);
      return nullptr;
    }
    return new CheckedStream(file, path);
  }

 private:
  size_t max_bytes_;
  std::string* problem_;  ///< the first file refused, for the error
};

/// A material's texture as the importer's child finds it; the parent decodes it (TextureCache).
struct TextureRef {
  enum class Kind { kNone, kFile, kEncoded, kTexels };
  Kind kind = Kind::kNone;
  std::string source;  ///< the file; for an image embedded in the mesh, the mesh and the image's name
  std::string bytes;   ///< kEncoded: a PNG or JPEG file's bytes; kTexels: RGBA, rows as assimp gives them
  int width = 0;       ///< kTexels [px]
  int height = 0;
};

/// What the importer's child sends back: the mesh, its materials' textures still to decode, and warnings.
struct ImportedMesh {
  TriangleMesh mesh;
  std::vector<TextureRef> textures;  ///< parallel to mesh.materials
  std::vector<std::string> warnings;
};

template <class A>
void fields(A& a, TextureRef& t) {
  a(t.kind, t.source, t.bytes, t.width, t.height);
}
template <class A>
void fields(A& a, ImportedMesh& m) {
  a(m.mesh, m.textures, m.warnings);
}

/// Where Gazebo looks for a texture a mesh names: beside the mesh, then in the model's materials/textures
/// (common/Material.cc); an absolute path as it is. "file://" prefixes are dropped.
std::vector<fs::path> textureCandidates(const std::string& mesh_path, std::string name) {
  if (name.rfind("file://", 0) == 0) name.erase(0, 7);
  if (fs::path(name).is_absolute()) return {name};
  const fs::path directory = fs::path(mesh_path).parent_path();
  return {directory / name, directory / ".." / "materials" / "textures" / name};
}

/// An image embedded in the mesh file (glTF, FBX): compressed bytes, or raw BGRA texels as RGBA.
TextureRef embeddedTexture(const aiTexture& embedded, const std::string& source, std::string* problem) {
  TextureRef ref;
  ref.source = source;
  if (embedded.mHeight == 0) {  // mWidth bytes of a PNG or JPEG file
    if (embedded.mWidth > kMaxTextureFileBytes) {
      *problem = "image [" + source + "] of " + std::to_string(embedded.mWidth) + " bytes is too large";
      return {};
    }
    ref.kind = TextureRef::Kind::kEncoded;
    ref.bytes.assign(reinterpret_cast<const char*>(embedded.pcData), embedded.mWidth);
    return ref;
  }
  const int64_t pixels = static_cast<int64_t>(embedded.mWidth) * embedded.mHeight;
  if (pixels > TextureLimits{}.max_pixels) {
    *problem = "image [" + source + "] of " + std::to_string(embedded.mWidth) + " x " +
               std::to_string(embedded.mHeight) + " px is larger than bullet_sim draws";
    return {};
  }
  ref.kind = TextureRef::Kind::kTexels;
  ref.width = static_cast<int>(embedded.mWidth);
  ref.height = static_cast<int>(embedded.mHeight);
  ref.bytes.reserve(static_cast<size_t>(pixels) * 4);
  for (int64_t i = 0; i < pixels; ++i) {
    const aiTexel& texel = embedded.pcData[i];
    ref.bytes.append({static_cast<char>(texel.r), static_cast<char>(texel.g), static_cast<char>(texel.b),
                      static_cast<char>(texel.a)});
  }
  return ref;
}

/// Where the diffuse (or glTF base colour) texture a material names is; none, with a warning, when it names
/// one that cannot be found.
TextureRef diffuseTexture(const aiScene& scene, const aiMaterial& material, const std::string& mesh_path,
                          std::vector<std::string>& warnings) {
  aiString name;
  if (material.GetTexture(aiTextureType_DIFFUSE, 0, &name) != AI_SUCCESS &&
      material.GetTexture(aiTextureType_BASE_COLOR, 0, &name) != AI_SUCCESS) {
    return {};
  }
  std::string problem;
  TextureRef ref;
  if (const aiTexture* embedded = scene.GetEmbeddedTexture(name.C_Str())) {
    ref = embeddedTexture(*embedded, mesh_path + " " + name.C_Str(), &problem);
  } else {
    const std::vector<fs::path> candidates = textureCandidates(mesh_path, name.C_Str());
    std::error_code ec;
    const auto found = std::find_if(candidates.begin(), candidates.end(),
                                    [&](const fs::path& candidate) { return fs::exists(candidate, ec); });
    if (found != candidates.end()) {
      ref.kind = TextureRef::Kind::kFile;
      ref.source = found->lexically_normal().string();
    } else {
      problem = "texture [" + std::string(name.C_Str()) + "] not found; looked for";
      for (const fs::path& candidate : candidates)
        problem += " [" + candidate.lexically_normal().string() + "]";
    }
  }
  if (!problem.empty())
    warnings.push_back("mesh [" + mesh_path + "]: " + problem +
                       "; that part is drawn in its material colour");
  return ref;
}

/// The file's materials, by assimp's index, and their textures (when `with_textures`); none when none gives a
/// colour or a texture. assimp's stand-in for files without materials (STL) gives none.
void readMaterials(const aiScene& scene, const std::string& mesh_path, bool with_textures,
                   ImportedMesh& imported) {
  std::vector<MeshMaterial>& materials = imported.mesh.materials;
  materials.assign(scene.mNumMaterials, MeshMaterial());
  imported.textures.assign(scene.mNumMaterials, TextureRef());
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
    if (with_textures) imported.textures[m] = diffuseTexture(scene, material, mesh_path, imported.warnings);
    any = any || materials[m].rgba || imported.textures[m].kind != TextureRef::Kind::kNone;
  }
  if (any) return;
  materials.clear();
  imported.textures.clear();
}

/// Appends one assimp mesh, placed by `transform` and scaled, to `mesh`: its vertices, texture coordinates
/// (when `with_uvs`), triangles and, when the file has materials, its part. Throws std::runtime_error naming
/// the problem (a bad index, too many triangles, a vertex beyond the limits).
void appendMesh(const aiMesh& sub, const aiMatrix4x4& transform, const Eigen::Vector3d& scale, bool with_uvs,
                const Limits& limits, TriangleMesh& mesh) {
  const size_t base = mesh.vertices.size();
  const int first = static_cast<int>(mesh.triangles.size());
  for (unsigned f = 0; f < sub.mNumFaces; ++f) {
    const aiFace& face = sub.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines carry no surface
    std::array<int, 3> triangle{};
    for (int k = 0; k < 3; ++k) {
      if (face.mIndices[k] >= sub.mNumVertices) throw std::runtime_error("a face names a vertex it lacks");
      triangle[k] = static_cast<int>(base + face.mIndices[k]);
    }
    mesh.triangles.push_back(triangle);
  }
  if (mesh.triangles.size() > limits.max_triangles) {
    throw std::runtime_error("it has more than " + std::to_string(limits.max_triangles) +
                             " triangles, the limit (max_triangles): simplify it");
  }
  for (unsigned v = 0; v < sub.mNumVertices; ++v) {
    const aiVector3D p = transform * sub.mVertices[v];
    const Eigen::Vector3d vertex(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
    if (!(vertex.cwiseAbs().maxCoeff() <= limits.max_length)) {  // also false for NaN
      std::ostringstream message;
      message << "vertex [" << vertex.transpose() << "] is not finite or beyond " << limits.max_length
              << " m (max_length): check the file and the scale";
      throw std::runtime_error(message.str());
    }
    mesh.vertices.push_back(vertex);
    if (!with_uvs) continue;
    const aiVector3D uv = sub.HasTextureCoords(0) ? sub.mTextureCoords[0][v] : aiVector3D();
    mesh.uvs.emplace_back(uv.x, uv.y);
  }
  const int count = static_cast<int>(mesh.triangles.size()) - first;
  if (mesh.materials.empty() || count == 0) return;
  const int material = static_cast<int>(sub.mMaterialIndex);
  if (material >= static_cast<int>(mesh.materials.size()))
    throw std::runtime_error("a mesh names a material it lacks");
  if (!mesh.parts.empty() && mesh.parts.back().material == material) {
    mesh.parts.back().triangle_count += count;
  } else {
    mesh.parts.push_back({first, count, material});
  }
}

/// Every triangle of the scene's meshes, each placed by its nodes' transforms, scaled, with the materials;
/// throws std::runtime_error naming the problem.
ImportedMesh collectTriangles(const aiScene& scene, const std::string& path, const Eigen::Vector3d& scale,
                              bool with_textures, const Limits& limits) {
  ImportedMesh imported;
  readMaterials(scene, path, with_textures, imported);
  const bool with_uvs =
      std::any_of(imported.textures.begin(), imported.textures.end(),
                  [](const TextureRef& ref) { return ref.kind != TextureRef::Kind::kNone; });
  // Iterative: a file may nest nodes deeper than any stack. Node transforms place each sub-mesh (DAE and OBJ
  // files nest them); STL has just the root.
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> todo{{scene.mRootNode, aiMatrix4x4()}};
  while (!todo.empty()) {
    const auto [node, parent] = todo.back();
    todo.pop_back();
    const aiMatrix4x4 transform = parent * node->mTransformation;
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      if (node->mMeshes[m] >= scene.mNumMeshes) throw std::runtime_error("a node names a mesh it lacks");
      appendMesh(*scene.mMeshes[node->mMeshes[m]], transform, scale, with_uvs, limits, imported.mesh);
    }
    // Children pushed last first, so that they are taken in file order (parts follow the file).
    for (unsigned c = node->mNumChildren; c > 0; --c) todo.emplace_back(node->mChildren[c - 1], transform);
  }
  if (imported.mesh.triangles.empty()) throw std::runtime_error("it has no triangles");
  return imported;
}

/// nullopt, with `error` (when given) saying "cannot load mesh [path]: why".
std::nullopt_t meshError(const std::string& path, const std::string& why, std::string* error) {
  if (error) *error = "cannot load mesh [" + path + "]: " + why;
  return std::nullopt;
}

/// The import's work, in whichever process runs it; what is wrong goes to `why`.
std::optional<ImportedMesh> importTriangles(const std::string& path, const Eigen::Vector3d& scale,
                                            bool with_textures, const Limits& limits, std::string* why) {
  if (auto problem = fileProblem(path, limits.max_mesh_bytes, "max_mesh_bytes")) {
    *why = "it " + *problem;
    return std::nullopt;
  }
  Assimp::Importer importer;
  std::string refused;
  importer.SetIOHandler(new RegularFileSystem(limits.max_mesh_bytes, &refused));  // the importer owns it
  // COLLADA as RViz, Gazebo, FCL and MoveIt read it: the vertices in the file's axes, scaled by its <unit
  // meter>, without assimp's turn of a Z_UP file into Y_UP (which stood a Z_UP jersey barrier on its end).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  try {
    if (!refused.empty()) throw std::runtime_error("the file it names, " + refused);
    if (!scene || !scene->mRootNode) {
      const std::string said = importer.GetErrorString();
      // assimp catches what it throws, running out of memory too, and says only its name.
      if (said.find("bad_alloc") != std::string::npos) {
        throw std::runtime_error(
            "the importer (assimp) ran out of the memory it may use on it: the file is corrupt or not "
            "a mesh; re-export it as STL, DAE or OBJ");
      }
      throw std::runtime_error(said);
    }
    return collectTriangles(*scene, path, scale, with_textures, limits);
  } catch (const std::runtime_error& e) {
    *why = e.what();
    return std::nullopt;
  }
}

/// The mesh with its textures decoded through `textures`; a texture that cannot be is a warning.
TriangleMesh attachTextures(ImportedMesh imported, const std::string& path, TextureCache* textures,
                            std::vector<std::string>* warnings) {
  if (warnings) warnings->insert(warnings->end(), imported.warnings.begin(), imported.warnings.end());
  if (!textures) return std::move(imported.mesh);
  for (size_t m = 0; m < imported.textures.size(); ++m) {
    TextureRef& ref = imported.textures[m];
    std::string error;
    std::shared_ptr<const Texture> texture;
    switch (ref.kind) {
      case TextureRef::Kind::kNone:
        continue;
      case TextureRef::Kind::kFile:
        texture = textures->load(ref.source, &error);
        break;
      case TextureRef::Kind::kEncoded:
        texture = textures->decode(reinterpret_cast<const uint8_t*>(ref.bytes.data()), ref.bytes.size(),
                                   ref.source, &error);
        break;
      case TextureRef::Kind::kTexels:
        texture =
            textures->adopt(Texture{ref.width, ref.height,
                                    std::vector<uint8_t>(ref.bytes.begin(), ref.bytes.end()), ref.source},
                            &error);
        break;
    }
    imported.mesh.materials[m].texture = texture;
    if (!texture && warnings)
      warnings->push_back("mesh [" + path + "]: " + error + "; that part is drawn in its material colour");
  }
  return std::move(imported.mesh);
}

std::string encode(const ImportedMesh& imported) {
  ByteWriter out;
  out(imported);
  return out.take();
}

std::optional<ImportedMesh> decode(const std::string& bytes) {
  try {
    ByteReader in(bytes);
    ImportedMesh imported;
    in(imported);
    return imported;
  } catch (const std::runtime_error&) {
    return std::nullopt;
  }
}

}  // namespace

std::optional<TriangleMesh> importMesh(const std::string& path, const Eigen::Vector3d& scale,
                                       std::string* error, TextureCache* textures,
                                       std::vector<std::string>* warnings, const Limits& limits) {
  std::string why;
  std::optional<ImportedMesh> imported = importTriangles(path, scale, textures != nullptr, limits, &why);
  if (!imported) return meshError(path, why, error);
  return attachTextures(std::move(*imported), path, textures, warnings);
}

std::optional<TriangleMesh> loadMesh(const std::string& path, const Eigen::Vector3d& scale,
                                     std::string* error, TextureCache* textures,
                                     std::vector<std::string>* warnings, const Limits& limits) {
  // Checked here too, so that a FIFO or a huge file is refused without a process to start.
  if (auto problem = fileProblem(path, limits.max_mesh_bytes, "max_mesh_bytes"))
    return meshError(path, "it " + *problem, error);
  struct stat status {};
  stat(path.c_str(), &status);
  const size_t memory = kImportMemoryBase + kImportMemoryPerFileByte * static_cast<size_t>(status.st_size);
  const ChildOutcome outcome = runInChild(
      [&] {
        std::string why;
        const std::optional<ImportedMesh> imported =
            importTriangles(path, scale, textures != nullptr, limits, &why);
        if (!imported) throw std::runtime_error(why);
        return encode(*imported);
      },
      memory, limits.mesh_import_seconds);
  const auto fail = [&](const std::string& why) { return meshError(path, why, error); };
  switch (outcome.ending) {
    case ChildOutcome::Ending::kReturned:
      if (auto imported = decode(outcome.output))
        return attachTextures(std::move(*imported), path, textures, warnings);
      return fail("the importer's answer was garbled");
    case ChildOutcome::Ending::kThrew:
      return fail(outcome.why);
    case ChildOutcome::Ending::kCrashed:
      return fail("the importer (assimp) crashed on it with " + outcome.why +
                  ": the file is corrupt or not a mesh; re-export it as STL, DAE or OBJ");
    case ChildOutcome::Ending::kTimedOut: {
      std::ostringstream why;
      why << "importing it took longer than " << limits.mesh_import_seconds
          << " s (mesh_import_seconds): the file is corrupt, or too large to import";
      return fail(why.str());
    }
    case ChildOutcome::Ending::kNotRun:
      return fail(outcome.why);
  }
  return fail("unexpected");
}

namespace {

/// Meshes alive anywhere in this process, by file (its size and time too, so that an edited file is read
/// again), scale and the limits they were checked against: the next copy of a model (a fleet's next robot)
/// shares them instead of importing the file again. A mesh no model holds any more is gone, and so is its
/// entry.
class LiveMeshes {
 public:
  struct Found {
    std::shared_ptr<const TriangleMesh> mesh;
    std::vector<std::string> warnings;  ///< what its import said, for every model that takes it
  };

  static LiveMeshes& instance() {
    static LiveMeshes live;
    return live;
  }

  static std::optional<std::string> key(const std::string& path, const Eigen::Vector3d& scale,
                                        const Limits& limits) {
    struct stat status {};
    if (stat(path.c_str(), &status) != 0) return std::nullopt;
    std::ostringstream key;
    key << path << '|' << scale.transpose() << '|' << status.st_size << '|' << status.st_mtim.tv_sec << '.'
        << status.st_mtim.tv_nsec << '|' << limits.max_mesh_bytes << '|' << limits.max_triangles << '|'
        << limits.max_length;
    return key.str();
  }

  std::optional<Found> find(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = meshes_.find(key);
    if (it == meshes_.end()) return std::nullopt;
    if (auto mesh = it->second.mesh.lock()) return Found{std::move(mesh), it->second.warnings};
    meshes_.erase(it);
    return std::nullopt;
  }

  void add(const std::string& key, const std::shared_ptr<const TriangleMesh>& mesh,
           std::vector<std::string> warnings) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = meshes_.begin(); it != meshes_.end();)
      it = it->second.mesh.expired() ? meshes_.erase(it) : std::next(it);
    meshes_[key] = {mesh, std::move(warnings)};
  }

 private:
  struct Entry {
    std::weak_ptr<const TriangleMesh> mesh;
    std::vector<std::string> warnings;
  };
  std::mutex mutex_;
  std::map<std::string, Entry> meshes_;
};

}  // namespace

std::shared_ptr<const TriangleMesh> MeshCache::load(const std::string& path, const Eigen::Vector3d& scale,
                                                    std::string* error, std::vector<std::string>* warnings) {
  std::ostringstream key;
  key << path << '|' << scale.transpose();
  std::shared_ptr<const TriangleMesh>& cached = meshes_[key.str()];
  if (cached) return cached;
  const std::optional<std::string> live_key = LiveMeshes::key(path, scale, limits_);
  if (live_key) {
    if (std::optional<LiveMeshes::Found> found = LiveMeshes::instance().find(*live_key)) {
      if (warnings) warnings->insert(warnings->end(), found->warnings.begin(), found->warnings.end());
      return cached = std::move(found->mesh);
    }
  }
  std::vector<std::string> said;
  if (std::optional<TriangleMesh> mesh = loadMesh(path, scale, error, &textures_, &said, limits_)) {
    cached = std::make_shared<const TriangleMesh>(std::move(*mesh));
    if (live_key) LiveMeshes::instance().add(*live_key, cached, said);
  }
  if (warnings) warnings->insert(warnings->end(), said.begin(), said.end());
  return cached;
}

}  // namespace bullet_sim
