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

/// Bullet's own rotation matrix, as it is (no round trip through a quaternion).
inline Eigen::Isometry3d fromBullet(const btTransform& pose) {
  Eigen::Isometry3d result;
  const btMatrix3x3& basis = pose.getBasis();
  for (int r = 0; r < 3; ++r) result.linear().row(r) = fromBullet(basis[r]);
  result.translation() = fromBullet(pose.getOrigin());
  result.makeAffine();
  return result;
}

/// Makes and owns Bullet shapes. Primitives stay analytic (URDF cylinders are btCylinderShapeZ); meshes
/// become their convex parts (a compound of hulls) on moving bodies, or a simplified hull where they have
/// none, and BVH triangle meshes on static ones.
class BulletShapes {
 public:
  /// nullptr for a plane on a moving body, which cannot exist.
  btCollisionShape* make(const Shape& shape, bool moving);
  btCompoundShape* makeCompound();
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
