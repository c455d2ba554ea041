#include "mesh_simplify.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace bullet_sim {

namespace {

/// [m] Vertices closer than this are the same vertex (STL files repeat each vertex in every triangle).
constexpr double kSameVertex = 1e-7;
/// The first cell tried is the mesh's diagonal over this times the square root of the budget; each try after
/// grows it by kCellGrowth.
constexpr double kFirstCellDivisor = 2;
constexpr double kCellGrowth = 1.25;

using Cell = std::array<int64_t, 3>;

struct CellHash {
  size_t operator()(const Cell& cell) const {
    size_t hash = 0;
    for (int64_t index : cell) hash = hash * 1000003u ^ std::hash<int64_t>()(index);
    return hash;
  }
};

/// Merges the vertices that share a cell of side `cell` [m] into their mean, and drops the triangles that
/// collapse or repeat another.
SimplifiedMesh cluster(const TriangleMesh& mesh, double cell) {
  SimplifiedMesh out;
  std::unordered_map<Cell, int, CellHash> index_of;
  std::vector<Eigen::Vector3d> sums;
  std::vector<int> counts;
  std::vector<int> remap(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& vertex = mesh.vertices[i];
    const Cell key{static_cast<int64_t>(std::floor(vertex.x() / cell)),
                   static_cast<int64_t>(std::floor(vertex.y() / cell)),
                   static_cast<int64_t>(std::floor(vertex.z() / cell))};
    const auto [it, added] = index_of.emplace(key, static_cast<int>(sums.size()));
    if (added) {
      sums.push_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
    }
    sums[it->second] += vertex;
    ++counts[it->second];
    remap[i] = it->second;
  }
  out.vertices.reserve(sums.size());
  for (size_t i = 0; i < sums.size(); ++i) out.vertices.push_back((sums[i] / counts[i]).cast<float>());

  std::unordered_set<Cell, CellHash> seen;  // each kept triangle's vertices, sorted
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& source = mesh.triangles[t];
    const std::array<int, 3> triangle{remap[source[0]], remap[source[1]], remap[source[2]]};
    if (triangle[0] == triangle[1] || triangle[1] == triangle[2] || triangle[0] == triangle[2]) continue;
    Cell sorted{triangle[0], triangle[1], triangle[2]};
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) continue;
    out.triangles.push_back(triangle);
    out.source.push_back(static_cast<int>(t));
  }
  return out;
}

}  // namespace

SimplifiedMesh simplifyMesh(const TriangleMesh& mesh, size_t max_triangles) {
  SimplifiedMesh merged = cluster(mesh, kSameVertex);
  if (merged.triangles.size() <= max_triangles || mesh.vertices.empty()) return merged;
  Eigen::AlignedBox3d bounds;
  for (const auto& vertex : mesh.vertices) bounds.extend(vertex);
  const double diagonal = std::max(bounds.diagonal().norm(), kSameVertex);
  double cell =
      diagonal / (kFirstCellDivisor * std::sqrt(static_cast<double>(std::max<size_t>(max_triangles, 1))));
  for (;; cell *= kCellGrowth) {
    SimplifiedMesh coarse = cluster(mesh, cell);
    if (coarse.triangles.size() <= max_triangles || cell > 2 * diagonal) return coarse;
  }
}

}  // namespace bullet_sim
