#include "bullet_sim/model/convex_decomposition.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "assets/child_program.h"
#include "common/work_pool.h"
#include "model/coacd_program.h"

namespace bullet_sim {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPython = "/usr/bin/python3";
constexpr size_t kMemory = size_t{4} << 30;           // [bytes] for Python, numpy and CoACD
constexpr size_t kMaxAnswer = size_t{256} << 20;      // [bytes] of parts from CoACD
constexpr size_t kMaxPoints = 100000;                 // of one part's hull
constexpr const char* kMagic = "bullet_sim convex parts 1\n";
constexpr const char* kHullMagic = "bullet_sim convex hull 1\n";  // splitting it ran out of time
constexpr uint64_t kKeyBasis = 0xcbf29ce484222325ULL;  // FNV-1a's offset basis
constexpr uint64_t kCheckBasis = 0x84222325cbf29ce4ULL;

uint64_t fnv1a(const std::string& bytes, uint64_t hash) {
  for (const unsigned char byte : bytes) hash = (hash ^ byte) * 0x100000001b3ULL;
  return hash;
}

template <class T>
void append(std::string& bytes, const T& value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));  // little-endian: x86-64 and ARM64 alike
}

/// The mesh as kCoacdProgram reads it.
std::string meshBytes(const TriangleMesh& mesh) {
  std::string bytes;
  bytes.reserve(16 + 24 * mesh.vertices.size() + 12 * mesh.triangles.size());
  append(bytes, static_cast<uint64_t>(mesh.vertices.size()));
  append(bytes, static_cast<uint64_t>(mesh.triangles.size()));
  for (const Eigen::Vector3d& vertex : mesh.vertices)
    bytes.append(reinterpret_cast<const char*>(vertex.data()), 24);
  for (const std::array<int, 3>& triangle : mesh.triangles)
    bytes.append(reinterpret_cast<const char*>(triangle.data()), 12);
  return bytes;
}

/// Parts as kCoacdProgram writes them, from `offset` to the end of `bytes`; nullopt unless they are whole,
/// 1 to `max_parts` of them, each of 1 to kMaxPoints finite points.
std::optional<ConvexParts> parseParts(const std::string& bytes, size_t offset, size_t max_parts) {
  const auto read = [&](uint64_t& value) {
    if (bytes.size() - offset < sizeof(value)) return false;
    std::memcpy(&value, bytes.data() + offset, sizeof(value));
    offset += sizeof(value);
    return true;
  };
  uint64_t count = 0;
  if (offset > bytes.size() || !read(count) || count < 1 || count > max_parts) return std::nullopt;
  ConvexParts parts;
  for (uint64_t p = 0; p < count; ++p) {
    uint64_t points = 0;
    if (!read(points) || points < 1 || points > kMaxPoints || (bytes.size() - offset) / 24 < points)
      return std::nullopt;
    auto& hull = parts.hulls.emplace_back(points);
    for (Eigen::Vector3d& point : hull) {
      std::memcpy(point.data(), bytes.data() + offset, 24);
      offset += 24;
      if (!point.allFinite()) return std::nullopt;
    }
  }
  if (offset != bytes.size()) return std::nullopt;
  return parts;
}

std::string encodeParts(const ConvexParts& parts) {
  std::string bytes;
  append(bytes, static_cast<uint64_t>(parts.hulls.size()));
  for (const auto& hull : parts.hulls) {
    append(bytes, static_cast<uint64_t>(hull.size()));
    for (const Eigen::Vector3d& point : hull) bytes.append(reinterpret_cast<const char*>(point.data()), 24);
  }
  return bytes;
}

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return in ? std::string(std::istreambuf_iterator<char>(in), {}) : std::string();
}

/// Where an entry's body starts, when `bytes` begin with `magic` and then the check hash `check`.
std::optional<size_t> bodyOf(const std::string& bytes, const char* magic, uint64_t check) {
  const size_t header = std::strlen(magic) + sizeof(check);
  if (bytes.size() < header || bytes.compare(0, std::strlen(magic), magic) != 0) return std::nullopt;
  uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + std::strlen(magic), sizeof(stored));
  if (stored != check) return std::nullopt;
  return header;
}

/// A cache entry: kMagic, the check hash, then the parts.
std::optional<ConvexParts> readEntry(const std::string& bytes, uint64_t check, size_t max_parts) {
  const std::optional<size_t> body = bodyOf(bytes, kMagic, check);
  if (!body) return std::nullopt;
  return parseParts(bytes, *body, max_parts);
}

/// Writes `bytes` to `path` through a file of its own beside it, renamed into place, so that no reader sees
/// half of it; a cache that cannot be written is no error.
void writeAtomically(const fs::path& path, const std::string& bytes) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  const fs::path temporary = path.string() + ".tmp" + std::to_string(getpid());
  std::ofstream out(temporary, std::ios::binary);
  out << bytes;
  out.close();
  if (out) fs::rename(temporary, path, ec);
  if (!out || ec) fs::remove(temporary, ec);
}

/// A cache entry: kMagic, the check hash, then the parts.
void writeEntry(const fs::path& path, uint64_t check, const ConvexParts& parts) {
  std::string bytes = kMagic;
  append(bytes, check);
  writeAtomically(path, bytes + encodeParts(parts));
}

/// Remembers that splitting took longer than `seconds`, so that the next spawn does not wait for it again.
void writeTimeout(const fs::path& path, uint64_t check, double seconds) {
  std::string bytes = kHullMagic;
  append(bytes, check);
  append(bytes, seconds);
  writeAtomically(path, bytes);
}

/// A timed-out entry: kHullMagic, the check hash, then the seconds [s] splitting had; nullopt when `bytes`
/// are no such entry for `check`.
std::optional<double> readTimeout(const std::string& bytes, uint64_t check) {
  const std::optional<size_t> body = bodyOf(bytes, kHullMagic, check);
  if (!body || bytes.size() != *body + sizeof(double)) return std::nullopt;
  double seconds = 0;
  std::memcpy(&seconds, bytes.data() + *body, sizeof(seconds));
  if (!(seconds > 0)) return std::nullopt;
  return seconds;
}

/// The last line of what a program wrote on stderr.
std::string lastLine(std::string text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  const size_t newline = text.rfind('\n');
  return newline == std::string::npos ? text : text.substr(newline + 1);
}

/// The links that never move: a root named "world" and the links on fixed joints down from it.
std::set<std::string> linksFixedToTheWorld(const ModelSpec& model) {
  std::set<std::string> still;
  if (model.root != "world") return still;
  still.insert(model.root);
  for (const JointSpec& joint : model.joints)  // parents come before their children
    if (joint.type == JointSpec::Type::kFixed && still.count(joint.parent)) still.insert(joint.child);
  return still;
}

}  // namespace

std::string convexCacheDir() {
  if (const char* dir = std::getenv("BULLET_SIM_CACHE_DIR"); dir && *dir) return std::string(dir) + "/convex";
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && *xdg) return std::string(xdg) + "/bullet_sim/convex";
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : "/tmp") + "/.cache/bullet_sim/convex";
}

ConvexDecomposer::ConvexDecomposer(std::string cache_dir, int threads)
    : cache_dir_(std::move(cache_dir)),
      threads_(threads > 0 ? threads : defaultPoolThreads()) {}

struct ConvexDecomposer::Split {
  uint64_t key = 0;
  uint64_t check = 0;
  fs::path entry;
  std::string mesh_bytes;
  ProgramOutcome outcome;
};

std::shared_ptr<const ConvexParts> ConvexDecomposer::decompose(const TriangleMesh& mesh, const Limits& limits,
                                                               std::string* warning) {
  std::vector<std::string> warnings;
  auto parts = decomposeAll({&mesh}, limits, warnings);
  if (warning && !warnings[0].empty()) *warning = warnings[0];
  return parts[0];
}

std::vector<std::shared_ptr<const ConvexParts>> ConvexDecomposer::decomposeAll(
    const std::vector<const TriangleMesh*>& meshes, const Limits& limits,
    std::vector<std::string>& warnings) {
  std::vector<std::shared_ptr<const ConvexParts>> parts(meshes.size());
  warnings.assign(meshes.size(), "");
  if (limits.max_convex_parts <= 1) return parts;
  // The settings are part of the key: the program and the most parts.
  const std::string settings = std::string(kCoacdProgram) + std::to_string(limits.max_convex_parts);
  std::vector<Split> splits;
  std::vector<std::optional<size_t>> split_of(meshes.size());  // which of `splits` makes a mesh's parts
  for (size_t m = 0; m < meshes.size(); ++m) {
    std::string bytes = meshBytes(*meshes[m]);
    const uint64_t key = fnv1a(bytes, fnv1a(settings, kKeyBasis));
    const auto pending =
        std::find_if(splits.begin(), splits.end(), [&](const Split& split) { return split.key == key; });
    if (pending != splits.end()) {
      split_of[m] = static_cast<size_t>(pending - splits.begin());
      continue;
    }
    if (const auto known = known_.find(key); known != known_.end()) {
      parts[m] = known->second;
      continue;
    }
    std::ostringstream name;
    name << std::hex << key << ".convex";
    const fs::path entry = fs::path(cache_dir_) / name.str();
    const uint64_t check = fnv1a(bytes, fnv1a(settings, kCheckBasis));
    const std::string stored = readAll(entry);
    if (auto cached = readEntry(stored, check, limits.max_convex_parts)) {
      parts[m] = known_[key] = std::make_shared<const ConvexParts>(std::move(*cached));
    } else if (const auto had = readTimeout(stored, check); had && *had >= limits.decomposition_seconds) {
      known_[key] = nullptr;
      std::ostringstream why;
      why << "splitting it into convex parts took longer than " << *had
          << " s (decomposition_seconds) before, as " << entry.string()
          << " remembers: it collides by its hull (a longer decomposition_seconds tries again)";
      warnings[m] = why.str();
    } else if (!coacd_missing_) {
      split_of[m] = splits.size();
      splits.push_back({key, check, entry, std::move(bytes), {}});
    }
  }
  WorkPool pool(static_cast<int>(std::min(splits.size(), static_cast<size_t>(threads_))));
  pool.run(splits.size(), [&](size_t s) {
    splits[s].outcome = runProgram({kPython, "-c", kCoacdProgram, std::to_string(limits.max_convex_parts)},
                                   splits[s].mesh_bytes, kMemory, limits.decomposition_seconds, kMaxAnswer);
  });
  std::vector<std::string> split_warnings(splits.size());
  for (size_t s = 0; s < splits.size(); ++s)
    known_[splits[s].key] = partsOf(splits[s], limits, &split_warnings[s]);
  for (size_t m = 0; m < meshes.size(); ++m) {
    if (!split_of[m]) continue;
    parts[m] = known_[splits[*split_of[m]].key];
    warnings[m] = std::exchange(split_warnings[*split_of[m]], "");  // said for its first mesh only
  }
  return parts;
}

std::shared_ptr<const ConvexParts> ConvexDecomposer::partsOf(const Split& split, const Limits& limits,
                                                             std::string* warning) {
  const ProgramOutcome& outcome = split.outcome;
  std::ostringstream why;
  if (outcome.ending == ProgramOutcome::Ending::kExited && outcome.status == 0) {
    if (auto parts = parseParts(outcome.output, 0, limits.max_convex_parts)) {
      writeEntry(split.entry, split.check, *parts);
      return std::make_shared<const ConvexParts>(std::move(*parts));
    }
    why << "CoACD's answer was garbled";
  } else if (outcome.ending == ProgramOutcome::Ending::kExited && outcome.status == 3) {
    if (coacd_missing_) return nullptr;  // said once
    coacd_missing_ = true;
    why << "CoACD is not installed (" << lastLine(outcome.errors)
        << "): moving meshes collide by their hulls; install it with `" << kPython
        << " -m pip install --break-system-packages coacd` (scripts/workspace.sh install does)";
  } else if (outcome.ending == ProgramOutcome::Ending::kTimedOut) {
    writeTimeout(split.entry, split.check, limits.decomposition_seconds);
    why << "splitting it into convex parts took longer than " << limits.decomposition_seconds
        << " s (decomposition_seconds)";
  } else if (outcome.ending == ProgramOutcome::Ending::kExited) {
    why << "CoACD failed on it: " << lastLine(outcome.errors);
  } else {
    why << "CoACD could not split it: " << (outcome.why.empty() ? lastLine(outcome.errors) : outcome.why);
  }
  *warning = why.str() + (coacd_missing_ ? "" : ": it collides by its hull");
  return nullptr;
}

void ConvexDecomposer::attach(ModelSpec& model, const Limits& limits, Diagnostics& diagnostics) {
  if (model.is_static) return;
  const std::set<std::string> still = linksFixedToTheWorld(model);
  std::vector<Shape*> shapes;
  std::vector<std::string> sources;  // "link [...] <collision> mesh [...]" of each
  for (LinkSpec& link : model.links) {
    if (still.count(link.name)) continue;
    for (Collision& collision : link.collisions) {
      Shape& shape = collision.shape;
      if (shape.type != Shape::Type::kMesh || !shape.mesh) continue;
      shapes.push_back(&shape);
      sources.push_back("link [" + link.name + "] <collision> mesh [" + shape.mesh_path + "]: ");
    }
  }
  std::vector<const TriangleMesh*> meshes;
  for (const Shape* shape : shapes) meshes.push_back(shape->mesh.get());
  std::vector<std::string> warnings;
  const auto parts = decomposeAll(meshes, limits, warnings);
  for (size_t k = 0; k < shapes.size(); ++k) {
    shapes[k]->convex_parts = parts[k];
    if (!warnings[k].empty()) diagnostics.warning(sources[k] + warnings[k]);
  }
}

}  // namespace bullet_sim
