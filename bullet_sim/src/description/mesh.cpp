#include "bullet_sim/description/mesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/DefaultIOStream.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>

#include <cerrno>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "bullet_sim/description/files.h"
#include "description/child_process.h"

namespace bullet_sim {

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

/// Every triangle of the scene's meshes, each placed by its nodes' transforms, scaled; throws
/// std::runtime_error naming the problem (a bad index, too many triangles, a vertex beyond the limits).
TriangleMesh collectTriangles(const aiScene& scene, const Eigen::Vector3d& scale, const Limits& limits) {
  TriangleMesh mesh;
  // Iterative: a file may nest nodes deeper than any stack.
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> todo{{scene.mRootNode, aiMatrix4x4()}};
  while (!todo.empty()) {
    const auto [node, parent] = todo.back();
    todo.pop_back();
    const aiMatrix4x4 transform = parent * node->mTransformation;
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      if (node->mMeshes[m] >= scene.mNumMeshes) throw std::runtime_error("a node names a mesh it lacks");
      const aiMesh& sub = *scene.mMeshes[node->mMeshes[m]];
      const size_t base = mesh.vertices.size();
      for (unsigned f = 0; f < sub.mNumFaces; ++f) {
        const aiFace& face = sub.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines carry no surface
        std::array<int, 3> triangle{};
        for (int k = 0; k < 3; ++k) {
          if (face.mIndices[k] >= sub.mNumVertices)
            throw std::runtime_error("a face names a vertex it lacks");
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
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) todo.emplace_back(node->mChildren[c], transform);
  }
  if (mesh.triangles.empty()) throw std::runtime_error("it has no triangles");
  return mesh;
}

/// The mesh as bytes through the child's pipe: counts, then the vertices and the triangles as they lie.
std::string encode(const TriangleMesh& mesh) {
  const uint64_t counts[2] = {mesh.vertices.size(), mesh.triangles.size()};
  std::string bytes(reinterpret_cast<const char*>(counts), sizeof(counts));
  bytes.append(reinterpret_cast<const char*>(mesh.vertices.data()),
               mesh.vertices.size() * sizeof(Eigen::Vector3d));
  bytes.append(reinterpret_cast<const char*>(mesh.triangles.data()),
               mesh.triangles.size() * sizeof(std::array<int, 3>));
  return bytes;
}

std::optional<TriangleMesh> decode(const std::string& bytes) {
  uint64_t counts[2];
  if (bytes.size() < sizeof(counts)) return std::nullopt;
  std::memcpy(counts, bytes.data(), sizeof(counts));
  const size_t vertex_bytes = counts[0] * sizeof(Eigen::Vector3d);
  const size_t triangle_bytes = counts[1] * sizeof(std::array<int, 3>);
  if (bytes.size() != sizeof(counts) + vertex_bytes + triangle_bytes) return std::nullopt;
  TriangleMesh mesh;
  mesh.vertices.resize(counts[0]);
  mesh.triangles.resize(counts[1]);
  std::memcpy(static_cast<void*>(mesh.vertices.data()), bytes.data() + sizeof(counts), vertex_bytes);
  std::memcpy(mesh.triangles.data(), bytes.data() + sizeof(counts) + vertex_bytes, triangle_bytes);
  return mesh;
}

/// nullopt, with `error` (when given) saying "cannot load mesh [path]: why".
std::nullopt_t meshError(const std::string& path, const std::string& why, std::string* error) {
  if (error) *error = "cannot load mesh [" + path + "]: " + why;
  return std::nullopt;
}

/// importMesh's work; what is wrong goes to `why`.
std::optional<TriangleMesh> importTriangles(const std::string& path, const Eigen::Vector3d& scale,
                                            const Limits& limits, std::string* why) {
  if (auto problem = fileProblem(path, limits.max_mesh_bytes, "max_mesh_bytes")) {
    *why = "it " + *problem;
    return std::nullopt;
  }
  Assimp::Importer importer;
  std::string refused;
  importer.SetIOHandler(new RegularFileSystem(limits.max_mesh_bytes, &refused));  // the importer owns it
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  try {
    if (!refused.empty()) throw std::runtime_error("the file it names, " + refused);
    if (!scene || !scene->mRootNode) {
      const std::string said = importer.GetErrorString();
      // assimp catches what it throws, running out of memory too, and says only its name.
      if (said.find("bad_alloc") != std::string::npos) {
        throw std::runtime_error(
            "the importer (assimp) ran out of the memory it may use on it: the file is corrupt or not a mesh; "
            "re-export it as STL, DAE or OBJ");
      }
      throw std::runtime_error(said);
    }
    return collectTriangles(*scene, scale, limits);
  } catch (const std::runtime_error& e) {
    *why = e.what();
    return std::nullopt;
  }
}

}  // namespace

std::optional<TriangleMesh> importMesh(const std::string& path, const Eigen::Vector3d& scale,
                                       std::string* error, const Limits& limits) {
  std::string why;
  if (auto mesh = importTriangles(path, scale, limits, &why)) return mesh;
  return meshError(path, why, error);
}

std::optional<TriangleMesh> loadMesh(const std::string& path, const Eigen::Vector3d& scale,
                                     std::string* error, const Limits& limits) {
  // Checked here too, so that a FIFO or a huge file is refused without a process to start.
  if (auto problem = fileProblem(path, limits.max_mesh_bytes, "max_mesh_bytes"))
    return meshError(path, "it " + *problem, error);
  struct stat status {};
  stat(path.c_str(), &status);
  const size_t memory = kImportMemoryBase + kImportMemoryPerFileByte * static_cast<size_t>(status.st_size);
  const ChildOutcome outcome = runInChild(
      [&] {
        std::string why;
        const std::optional<TriangleMesh> mesh = importTriangles(path, scale, limits, &why);
        if (!mesh) throw std::runtime_error(why);
        return encode(*mesh);
      },
      memory, limits.mesh_import_seconds);
  const auto fail = [&](const std::string& why) { return meshError(path, why, error); };
  switch (outcome.ending) {
    case ChildOutcome::Ending::kReturned:
      if (auto mesh = decode(outcome.output)) return mesh;
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

}  // namespace bullet_sim
