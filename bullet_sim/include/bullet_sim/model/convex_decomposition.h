// Moving collision meshes split into convex parts with CoACD (PyPI `coacd`), so that links collide by shapes
// close to their meshes, not by one hull that overlaps the next link. Each mesh is split once per machine:
// the parts are kept in a cache keyed by a hash of the mesh and the settings.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

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
/// The meshes of one model split side by side, one CoACD process per thread; each mesh's parts depend on that
/// mesh alone, so they are the same whatever the number of threads and whichever process ends first.
class ConvexDecomposer {
 public:
  /// `threads`: CoACD processes at once; 0 (or less): the cores it may run on, at most 4.
  explicit ConvexDecomposer(std::string cache_dir = convexCacheDir(), int threads = 0);

  /// The convex parts of `mesh`; nullptr when it collides by its hull: limits.max_convex_parts is 1, or
  /// splitting it failed, and then `warning` says why (the first time only).
  std::shared_ptr<const ConvexParts> decompose(const TriangleMesh& mesh, const Limits& limits,
                                               std::string* warning);

  /// decompose() for each of `meshes` (side by side); `warnings` gets one entry per mesh, empty but where
  /// it keeps its hull the first time.
  std::vector<std::shared_ptr<const ConvexParts>> decomposeAll(const std::vector<const TriangleMesh*>& meshes,
                                                               const Limits& limits,
                                                               std::vector<std::string>& warnings);

  /// Gives each mesh collision of `model` its convex parts, unless the model is static or the link is fixed
  /// to the world (such a link never moves: it collides by its triangles, as the world's meshes do); a
  /// warning in `diagnostics` names each mesh that keeps its hull.
  void attach(ModelSpec& model, const Limits& limits, Diagnostics& diagnostics);

 private:
  struct Split;  ///< a mesh neither known nor in the cache, to split

  /// The parts of `split` from what CoACD answered; nullptr and `warning` where it keeps its hull.
  std::shared_ptr<const ConvexParts> partsOf(const Split& split, const Limits& limits, std::string* warning);

  std::string cache_dir_;
  int threads_;
  std::map<uint64_t, std::shared_ptr<const ConvexParts>> known_;  ///< by key; nullptr: it keeps its hull
  bool coacd_missing_ = false;  ///< said once; then every mesh keeps its hull without a word
};

}  // namespace bullet_sim
