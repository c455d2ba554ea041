#include "physics/cylinder_plane.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>

#include <cmath>
#include <initializer_list>
#include <new>

namespace bullet_sim {

namespace {

constexpr btScalar kUprightSine = 1e-4;  ///< the axis this close to the normal: the cylinder stands on an end
constexpr btScalar kLevelDrop = 5e-4;    ///< [m] from one end of the tread to the other: it lies level

/// At most four points, without allocating: collision runs every substep for every wheel.
struct Points {
  btVector3 at[4];
  int count = 0;
  void push_back(const btVector3& point) { at[count++] = point; }
};

/// The points of `cylinder` (world pose `pose`) that may touch a plane of normal `normal`: one or two on its
/// lowest line, or four points of the lower end's rim when it stands on it.
Points lowestPoints(const btCylinderShape& cylinder, const btTransform& pose, const btVector3& normal) {
  const int up = cylinder.getUpAxis();
  const btVector3 extents = cylinder.getHalfExtentsWithMargin();
  const btScalar radius = extents[(up + 1) % 3], half_length = extents[up];
  const btVector3 axis = pose.getBasis().getColumn(up);
  Points points;
  btVector3 down = axis * normal.dot(axis) - normal;  // the way down the plane, across the axis
  if (down.length() > kUprightSine) {
    down.normalize();
    // Level, the tread's line contact bears at its middle, as a tyre's patch does (two points would twist
    // against a wheel turning about a point near it: a wheelchair turned 2.5 % slow). Tilted, at the middles
    // of its two halves, which carry a uniform line's load and hold it up as the line does.
    if (std::abs(normal.dot(axis)) * 2 * half_length < kLevelDrop) {
      points.push_back(pose.getOrigin() + down * radius);
      return points;
    }
    for (const btScalar at : {half_length / 2, -half_length / 2}) {
      points.push_back(pose.getOrigin() + axis * at + down * radius);
    }
    return points;
  }
  const btVector3 lower_end = pose.getOrigin() - axis * (normal.dot(axis) > 0 ? half_length : -half_length);
  btVector3 across, other;
  btPlaneSpace1(axis, across, other);
  for (const btVector3& spoke : {across, other, -across, -other}) {
    points.push_back(lower_end + spoke * radius);
  }
  return points;
}

}  // namespace

WorldPlane worldPlane(const btCollisionObjectWrapper& plane) {
  const auto& shape = *static_cast<const btStaticPlaneShape*>(plane.getCollisionShape());
  const btTransform& pose = plane.getWorldTransform();
  return {pose.getBasis() * shape.getPlaneNormal(),
          pose * (shape.getPlaneNormal() * shape.getPlaneConstant())};
}

CylinderPlaneAlgorithm::CylinderPlaneAlgorithm(btPersistentManifold* manifold,
                                               const btCollisionAlgorithmConstructionInfo& info,
                                               const btCollisionObjectWrapper* body0,
                                               const btCollisionObjectWrapper* body1, bool swapped)
    : btCollisionAlgorithm(info), manifold_(manifold), swapped_(swapped) {
  const btCollisionObject* cylinder = (swapped ? body1 : body0)->getCollisionObject();
  const btCollisionObject* plane = (swapped ? body0 : body1)->getCollisionObject();
  if (!manifold_ && m_dispatcher->needsCollision(cylinder, plane)) {
    manifold_ = m_dispatcher->getNewManifold(cylinder, plane);
    own_manifold_ = true;
  }
}

CylinderPlaneAlgorithm::~CylinderPlaneAlgorithm() {
  if (own_manifold_ && manifold_) m_dispatcher->releaseManifold(manifold_);
}

void CylinderPlaneAlgorithm::processCollision(const btCollisionObjectWrapper* body0,
                                              const btCollisionObjectWrapper* body1, const btDispatcherInfo&,
                                              btManifoldResult* result) {
  if (!manifold_) return;
  const btCollisionObjectWrapper* cylinder = swapped_ ? body1 : body0;
  const btCollisionObjectWrapper* plane = swapped_ ? body0 : body1;
  const auto [normal, on_plane] = worldPlane(*plane);
  result->setPersistentManifold(manifold_);
  const btScalar reach = manifold_->getContactBreakingThreshold() + result->m_closestPointDistanceThreshold;
  const Points points = lowestPoints(*static_cast<const btCylinderShape*>(cylinder->getCollisionShape()),
                                     cylinder->getWorldTransform(), normal);
  for (int i = 0; i < points.count; ++i) {
    const btScalar distance = normal.dot(points.at[i] - on_plane);
    if (distance < reach) result->addContactPoint(normal, points.at[i] - normal * distance, distance);
  }
  if (own_manifold_ && manifold_->getNumContacts()) result->refreshContactPoints();
}

void CylinderPlaneAlgorithm::getAllContactManifolds(btManifoldArray& manifolds) {
  if (manifold_ && own_manifold_) manifolds.push_back(manifold_);
}

btCollisionAlgorithm* CylinderPlaneAlgorithm::CreateFunc::CreateCollisionAlgorithm(
    btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* body0,
    const btCollisionObjectWrapper* body1) {
  void* memory = info.m_dispatcher1->allocateCollisionAlgorithm(sizeof(CylinderPlaneAlgorithm));
  return new (memory) CylinderPlaneAlgorithm(nullptr, info, body0, body1, m_swapped);
}

void CylinderPlaneAlgorithm::registerWith(btCollisionDispatcher& dispatcher, CreateFunc& cylinder_first,
                                          CreateFunc& plane_first) {
  cylinder_first.m_swapped = false;
  plane_first.m_swapped = true;
  dispatcher.registerCollisionCreateFunc(CYLINDER_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE, &cylinder_first);
  dispatcher.registerCollisionCreateFunc(STATIC_PLANE_PROXYTYPE, CYLINDER_SHAPE_PROXYTYPE, &plane_first);
}

}  // namespace bullet_sim
