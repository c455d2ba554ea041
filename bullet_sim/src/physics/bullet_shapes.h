// Bullet collision shapes for spec shapes, and Eigen <-> Bullet conversions (private to the physics layer).
#pragma once

#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>

#include <memory>
#include <vector>

#include "bullet_sim/model/geometry.h"

namespace bullet_sim {

inline btVector3 toBullet(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
inline Eigen::Vector3d fromBullet(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

inline btTransform toBullet(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), toBullet(pose.translation()));
}

/// The pose's rotation matrix as it is (no round trip through a quaternion).
inline btTransform toBulletExactly(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d& r = pose.linear();
  return btTransform(
      btMatrix3x3(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)),
      toBullet(pose.translation()));
}

/// Bullet's own rotation matrix, as it is (no round trip through a quaternion).
inline Eigen::Isometry3d fromBullet(const btTransform& pose) {
  Eigen::Isometry3d result;
  const btMatrix3x3& basis = pose.getBasis();
  for (int r = 0; r < 3; ++r) result.linear().row(r) = fromBullet(basis[r]);
  result.translation() = fromBullet(pose.getOrigin());
  result.makeAffine();
  return result;
}

/// A compound whose world bounds are taken about a frame of its owner's choice (a robot's root link) instead
/// of its own axes. A moving body's compound lies in its principal axes of inertia, which may lean far from
/// the robot's: the wheelchair, 1.2 m long, had bounds over 1.5 m wide in the world, which overlapped every
/// neighbour's on a grid 1.5 m apart, diagonals too, and those pairs cost ten of them 7 % of each step. The
/// children's bounds are taken again whenever Bullet recalculates the compound's; a compound given children
/// since keeps Bullet's bounds until then.
class FramedCompound : public btCompoundShape {
 public:
  /// `frame` in the compound's own frame.
  explicit FramedCompound(const btTransform& frame) : frame_(frame) {}
  void recalculateLocalAabb() override;
  void getAabb(const btTransform& pose, btVector3& min, btVector3& max) const override;

 private:
  btTransform frame_;
  btVector3 min_{0, 0, 0}, max_{0, 0, 0};  ///< the children's bounds in frame_
  int bounded_children_ = -1;              ///< how many children min_ and max_ bound
};

/// Makes and owns Bullet shapes. Primitives stay analytic (URDF cylinders are btCylinderShapeZ); meshes
/// become their convex parts (a compound of hulls) on moving bodies, or a simplified hull where they have
/// none, and BVH triangle meshes on static ones.
class BulletShapes {
 public:
  /// nullptr for a plane on a moving body, which cannot exist.
  btCollisionShape* make(const Shape& shape, bool moving);
  btCompoundShape* makeCompound();
  /// A compound whose world bounds are taken about `bounds_frame` (in its own frame).
  btCompoundShape* makeCompound(const btTransform& bounds_frame);
  /// Adds `shape` at `where` to `compound`: one child, or one per convex part of a moving mesh that has them
  /// (a compound in a compound would hide from contacts which child of the outer one touched). The number of
  /// children added; 0 for a plane on a moving body.
  int addTo(btCompoundShape& compound, const btTransform& where, const Shape& shape, bool moving);

 private:
  btCompoundShape* makeParts(const ConvexParts& parts);

  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btTriangleMesh>> triangle_meshes_;
};

}  // namespace bullet_sim
