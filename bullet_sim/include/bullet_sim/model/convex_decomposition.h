// Moving collision meshes split into convex parts with CoACD (PyPI `coacd`), so that links collide by shapes
// close to their meshes, not by one hull that overlaps the next link. Each mesh is split once per machine:
// the parts are kept in a cache keyed by a hash of the mesh and the settings.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/geometry.h"
#include "bullet_sim/common/limits.h"
#include "bullet_sim/model/model.h"

namespace bullet_sim {

/// Where ConvexDecomposer keeps its parts by default: $BULLET_SIM_CACHE_DIR/convex, else
/// $XDG_CACHE_HOME/bullet_sim/convex, else ~/.cache/bullet_sim/convex.
std::string convexCacheDir();

/// Splits meshes into convex parts. A mesh not in the cache is split by CoACD, run by /usr/bin/python3 in a
/// child process with bounded memory and limits.decomposition_seconds of wall time, into at most
/// limits.max_convex_parts parts. Where that fails (CoACD is not installed, the time ran out), the mesh keeps
/// colliding by its hull, with one warning. A split that ran out of time is remembered in the cache too, so
/// that the next spawn takes the hull at once; a longer decomposition_seconds than it had tries again.
class ConvexDecomposer {
 public:
  explicit ConvexDecomposer(std::string cache_dir = convexCacheDir()) : cache_dir_(std::move(cache_dir)) {}

  /// The convex parts of `mesh`; nullptr when it collides by its hull: limits.max_convex_parts is 1, or
  /// splitting it failed, and then `warning` says why (the first time only).
  std::shared_ptr<const ConvexParts> decompose(const TriangleMesh& mesh, const Limits& limits,
                                               std::string* warning);

  /// Gives each mesh collision of `model` its convex parts, unless the model is static; a warning in
  /// `diagnostics` names each mesh that keeps its hull.
  void attach(ModelSpec& model, const Limits& limits, Diagnostics& diagnostics);

 private:
  /// `timed_out` is set when CoACD ran out of limits.decomposition_seconds.
  std::shared_ptr<const ConvexParts> split(const std::string& mesh_bytes, const Limits& limits,
                                           std::string* warning, bool* timed_out);

  std::string cache_dir_;
  std::map<uint64_t, std::shared_ptr<const ConvexParts>> known_;  ///< by key; nullptr: it keeps its hull
  bool coacd_missing_ = false;  ///< said once; then every mesh keeps its hull without a word
};

}  // namespace bullet_sim
