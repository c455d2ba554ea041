// Exact, batched ray casting against collision shapes for range sensors (2D and 3D lidars), with Embree 3.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <vector>

#include "bullet_sim/model/geometry.h"

namespace bullet_sim {

/// Names a body of a RayCaster. Ids are never reused, even after removeBody.
using BodyId = int;
/// Passed as `ignore` to RayCaster::cast to ignore nothing.
constexpr BodyId kNoBody = -1;

/// Ray casting scene of rigid bodies. Boxes and meshes are triangles; spheres, cylinders and planes are
/// intersected analytically in double precision, so ranges agree with the true surfaces to a few micrometres
/// (Embree's rays are single precision) and grazing rays give no false hits.
///
/// Usage: add bodies, then per scan that is due: setPose() for the moving bodies (cheap, may also be called
/// every physics step), commit() once, then cast() any number of times.
///
/// Threads: cast() and castStatic() may run side by side. setPose() and a commit() of moved bodies alone may
/// run beside castStatic() (they change only what cast() sees), never beside cast().
///
/// Movable, not copyable. A moved-from caster may only be destroyed or assigned to.
class RayCaster {
 public:
  RayCaster();
  ~RayCaster();
  RayCaster(RayCaster&&) noexcept;
  RayCaster& operator=(RayCaster&&) noexcept;
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// Adds a rigid body made of `shapes` (origins in the body frame) at `pose` (body frame in the world).
  /// A static body never moves; all static bodies share one acceleration structure, which is fastest to
  /// cast against. A kMesh shape without a loaded mesh has no surface. A kPlane is infinite (in practice a
  /// disc of radius 1e6 m). Takes effect at the next commit().
  BodyId addBody(const std::vector<Collision>& shapes, const Eigen::Isometry3d& pose, bool is_static);

  /// Takes effect at the next commit(). Throws std::invalid_argument for an unknown body.
  void removeBody(BodyId body);

  /// Records the pose of a moving body; cast() sees it after the next commit().
  /// Throws std::invalid_argument for an unknown or static body.
  void setPose(BodyId body, const Eigen::Isometry3d& pose);

  /// Applies the bodies added, removed and moved since the last commit. Costs about one rebuild of a tree
  /// over the moving bodies (plus one over the static shapes when static bodies were added or removed), so
  /// call it once per scan that is due, not per physics step. Does nothing when nothing changed.
  void commit();

  /// Casts rays from `origin` [m] along the unit `directions` (world frame). Sets ranges[i] to the distance
  /// [m] to the first surface hit in [0, max_range], or to +infinity when nothing is hit within max_range.
  /// Surfaces of body `ignore` (e.g. the link the sensor sits on) are skipped; kNoBody skips none. Skipping
  /// a moving body is free while it has a ray mask of its own (4,495 bodies alive at once get one), skipping
  /// a static body or any other moving one slows the cast (1.5x for a sensor inside it).
  /// Runs on the calling thread; deterministic; allocates only when `ranges` lacks capacity.
  /// Throws std::logic_error when bodies were added or removed since the last commit(), and
  /// std::invalid_argument when `ignore` is neither kNoBody nor a body of this caster.
  void cast(const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3f>& directions, double max_range,
            BodyId ignore, std::vector<double>& ranges) const;

  /// Casts one ray per origin [m] along its unit direction against the static bodies only (e.g. the ground
  /// under each wheel). ranges[i] is the distance to the first static surface within max_range, or +infinity;
  /// with `normals`, (*normals)[i] is that surface's unit normal, facing the ray's origin; with `frictions`,
  /// (*frictions)[i] is its Collision's mu (unset for a miss).
  /// For a handful of rays per physics step: it casts them one by one.
  void castStatic(const std::vector<Eigen::Vector3d>& origins, const std::vector<Eigen::Vector3d>& directions,
                  double max_range, std::vector<double>& ranges,
                  std::vector<Eigen::Vector3d>* normals = nullptr,
                  std::vector<double>* frictions = nullptr) const;

 private:
  struct Impl;
  // Behind a pointer: keeps Embree out of this header and gives Embree's callbacks stable addresses.
  std::unique_ptr<Impl> impl_;
};

}  // namespace bullet_sim
