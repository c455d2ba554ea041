#include "physics/compound_plane.h"

#include <BulletCollision/BroadphaseCollision/btDbvt.h>
#include <BulletCollision/CollisionDispatch/btCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btCompoundCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btConvexPlaneCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <new>

#include "physics/contacts.h"
#include "physics/cylinder_plane.h"

namespace bullet_sim {

namespace {

/// [m] beyond a manifold's reach that a child's sphere must stay to be skipped: Bullet's own distances round.
constexpr btScalar kRoundingSlack = 1e-6;

/// Records the leaves of a tree in the order a traversal visits them.
struct LeafOrder : btDbvt::ICollide {
  std::vector<int>* order;
  void Process(const btDbvtNode* leaf) override { order->push_back(leaf->dataAsInt); }
};

const btCompoundShape& compoundOf(const btCollisionObjectWrapper& wrapper) {
  return *static_cast<const btCompoundShape*>(wrapper.getCollisionShape());
}

}  // namespace

CompoundPlaneAlgorithm::CompoundPlaneAlgorithm(const btCollisionAlgorithmConstructionInfo& info,
                                               const btCollisionObjectWrapper* body0,
                                               const btCollisionObjectWrapper* body1, bool swapped,
                                               bool skips_far_children)
    : btActivatingCollisionAlgorithm(info, body0, body1),
      swapped_(swapped),
      skips_far_children_(skips_far_children),
      shared_manifold_(info.m_manifold) {
  restart(compoundOf(*(swapped ? body1 : body0)));
}

CompoundPlaneAlgorithm::~CompoundPlaneAlgorithm() { freeChildren(); }

void CompoundPlaneAlgorithm::freeChildren() {
  for (btCollisionAlgorithm* child : children_) {
    if (!child) continue;
    child->~btCollisionAlgorithm();
    m_dispatcher->freeCollisionAlgorithm(child);
  }
  children_.clear();
}

void CompoundPlaneAlgorithm::release(int index) {
  btCollisionAlgorithm*& child = children_[index];
  child->~btCollisionAlgorithm();
  m_dispatcher->freeCollisionAlgorithm(child);
  child = nullptr;
  manifolds_.resize(0);  // held the child's manifold, which went with it
}

void CompoundPlaneAlgorithm::restart(const btCompoundShape& compound) {
  freeChildren();
  breaking_threshold_ = -1;
  children_.assign(compound.getNumChildShapes(), nullptr);
  // Bullet meets the children its tree finds within the plane's bounds, which are infinite: every leaf.
  const btDbvt& tree = *compound.getDynamicAabbTree();
  const btVector3 everywhere(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT);
  std::vector<int> indices;
  LeafOrder leaves;
  leaves.order = &indices;
  tree.collideTV(tree.m_root, btDbvtVolume::FromMM(-everywhere, everywhere), leaves);
  order_.clear();
  for (const int index : indices) {
    const btCollisionShape& shape = *compound.getChildShape(index);
    Child child{index, shape.isConvex(), btVector3(0, 0, 0), 0, false};
    shape.getBoundingSphere(child.centre, child.radius);
    order_.push_back(child);
  }
  revision_ = compound.getUpdateRevision();
}

/// What every child of the compound meets in one call: the plane, and what the compound's body can close. The
/// plane and the body's motion are also kept in the compound's frame, where each child is placed: a child's
/// tests then take its own transform only.
struct CompoundPlaneAlgorithm::Meeting {
  Meeting(const btCollisionObjectWrapper& compound, const btCollisionObjectWrapper& plane,
          const btDispatcherInfo& info, btManifoldResult& result, const btRigidBody* body);

  const btCollisionObjectWrapper& compound;
  const btCollisionObjectWrapper& plane;
  const btDispatcherInfo& info;
  btManifoldResult& result;
  /// The compound's rigid body, whose children may be out of reach: null for a multibody link (its velocity
  /// is its multibody's to tell), or where far children are never skipped.
  const btRigidBody* body;
  double turning = 0;  ///< [rad/s] the body's angular speed
  double gravity = 0;  ///< [m/s^2] on the body
  btVector3 up;        ///< the plane's normal, in the compound's frame
  btScalar height;     ///< [m] of the compound's origin over the plane
  btVector3 linear{0, 0, 0};   ///< [m/s] with a body: its velocity at the compound's origin, in its frame
  btVector3 angular{0, 0, 0};  ///< [rad/s] with a body: its angular velocity, in the compound's frame
};

CompoundPlaneAlgorithm::Meeting::Meeting(const btCollisionObjectWrapper& compound_in,
                                         const btCollisionObjectWrapper& plane_in,
                                         const btDispatcherInfo& info_in, btManifoldResult& result_in,
                                         const btRigidBody* body_in)
    : compound(compound_in), plane(plane_in), info(info_in), result(result_in), body(body_in) {
  const WorldPlane surface = worldPlane(plane);
  const btTransform& pose = compound.getWorldTransform();
  up = surface.normal * pose.getBasis();
  height = surface.normal.dot(pose.getOrigin() - surface.point);
  if (!body) return;
  turning = body->getAngularVelocity().length();
  gravity = body->getGravity().length();
  linear =
      body->getVelocityInLocalPoint(pose.getOrigin() - body->getCenterOfMassPosition()) * pose.getBasis();
  angular = body->getAngularVelocity() * pose.getBasis();
}

void CompoundPlaneAlgorithm::refreshManifolds(btManifoldResult& result) {
  for (int m = 0; m < manifolds_.size(); ++m) {
    if (!manifolds_[m]->getNumContacts()) continue;
    result.setPersistentManifold(manifolds_[m]);
    result.refreshContactPoints();
    result.setPersistentManifold(nullptr);
  }
}

void CompoundPlaneAlgorithm::processCollision(const btCollisionObjectWrapper* body0,
                                              const btCollisionObjectWrapper* body1,
                                              const btDispatcherInfo& info, btManifoldResult* result) {
  const btCollisionObjectWrapper& compound = *(swapped_ ? body1 : body0);
  const btCollisionObjectWrapper& plane = *(swapped_ ? body0 : body1);
  if (compoundOf(compound).getUpdateRevision() != revision_) restart(compoundOf(compound));
  // Bullet refreshes every child's manifold, then meets the children. A manifold of a child's own is touched
  // by nothing else: readyToMeet refreshes it just before the child is met, to the same effect.
  if (shared_manifold_) {
    for (btCollisionAlgorithm* child : children_) {
      if (!child) continue;
      manifolds_.resize(0);
      child->getAllContactManifolds(manifolds_);
      refreshManifolds(*result);
    }
  }
  const btRigidBody* body =
      skips_far_children_ ? btRigidBody::upcast(compound.getCollisionObject()) : nullptr;
  const Meeting meeting(compound, plane, info, *result, body);
  for (const Child& child : order_) processChild(child, meeting);
  // Bullet would now free the algorithms of children outside the plane's bounds: there are none.
}

bool CompoundPlaneAlgorithm::beyondReach(const Child& child, const Meeting& meeting) const {
  if (!child.convex || !skips_far_children_) return false;
  if (manifolds_.size() != 1 || manifolds_[0]->getNumContacts() > 0) return false;
  return sphereBeyond(child, meeting, manifolds_[0]->getContactBreakingThreshold());
}

bool CompoundPlaneAlgorithm::sphereBeyond(const Child& child, const Meeting& meeting,
                                          btScalar breaking_threshold) const {
  // Bullet's convex-plane algorithm then finds its support point too far and adds nothing; ours for cylinders
  // likewise.
  const btScalar reach = breaking_threshold + meeting.result.m_closestPointDistanceThreshold;
  // The child's transform as it is now: a kinematic joint moves a rim without a new revision of the compound.
  const btVector3 centre = compoundOf(meeting.compound).getChildTransform(child.index) * child.centre;
  return meeting.up.dot(centre) + meeting.height - child.radius > reach + kRoundingSlack;
}

bool CompoundPlaneAlgorithm::outOfReach(const Child& child, const Meeting& meeting) const {
  if (!child.convex || !meeting.body) return false;
  const btCompoundShape& shape = compoundOf(meeting.compound);
  const btTransform& placed = shape.getChildTransform(child.index);
  const auto& convex = *static_cast<const btConvexShape*>(shape.getChildShape(child.index));
  const btVector3 down = -meeting.up * placed.getBasis();  // in the child's frame
  const btVector3 lowest = placed * convex.localGetSupportingVertex(down);  // in the compound's frame
  const btVector3 velocity = meeting.linear + meeting.angular.cross(lowest);
  // Every point of the child lies within its sphere's diameter of the lowest: turning, none approaches faster
  // by more than that.
  const double approach =
      std::max(0.0, -static_cast<double>(velocity.dot(meeting.up))) + meeting.turning * 2 * child.radius;
  const double gap = meeting.up.dot(lowest) + meeting.height;
  return gap > reachableGap(approach, meeting.gravity, meeting.info.m_timeStep) + kRoundingSlack;
}

bool CompoundPlaneAlgorithm::readyToMeet(const Child& child, btCollisionAlgorithm& algorithm,
                                         const Meeting& meeting) {
  if (shared_manifold_) return true;  // refreshed with the others, before any child is met
  manifolds_.resize(0);
  algorithm.getAllContactManifolds(manifolds_);
  if (manifolds_.size() == 1) breaking_threshold_ = manifolds_[0]->getContactBreakingThreshold();
  if (beyondReach(child, meeting) || outOfReach(child, meeting)) {
    // A rigid body's child gives up its algorithm and its manifold (the points outOfReach drops go with it).
    // A multibody link's keeps an empty manifold, and its place in the solver's order: a contact robot's
    // results stay as they were (a car launched at 10 ms steps veers by how its wheels are ordered).
    if (meeting.body) release(child.index);
    return false;
  }
  refreshManifolds(meeting.result);
  return true;
}

bool CompoundPlaneAlgorithm::staysAway(const Child& child, const Meeting& meeting) const {
  if (!meeting.body || !child.convex || breaking_threshold_ < 0) return false;
  // Either test skips the child. A rim its spring holds over the ground reaches the plane with its sphere,
  // substep after substep, but not within the substep: a child whose sphere reached the plane when last
  // tested is tested for being out of reach first.
  const bool reach_tested_first = child.sphere_reaches;
  if (reach_tested_first && outOfReach(child, meeting)) return true;
  child.sphere_reaches = !sphereBeyond(child, meeting, breaking_threshold_);
  if (!child.sphere_reaches) return true;
  return !reach_tested_first && outOfReach(child, meeting);
}

void CompoundPlaneAlgorithm::processChild(const Child& child, const Meeting& meeting) {
  const btCollisionObjectWrapper& compound = meeting.compound;
  const btCollisionObjectWrapper& plane = meeting.plane;
  btManifoldResult& result = meeting.result;
  const btCompoundShape& shape = compoundOf(compound);
  const btCollisionShape* child_shape = shape.getChildShape(child.index);
  if (gCompoundChildShapePairCallback &&
      !gCompoundChildShapePairCallback(plane.getCollisionShape(), child_shape))
    return;
  btCollisionAlgorithm* algorithm = children_[child.index];
  if (algorithm ? !readyToMeet(child, *algorithm, meeting) : staysAway(child, meeting)) return;
  const btTransform& child_transform = shape.getChildTransform(child.index);
  const btTransform child_pose = compound.getWorldTransform() * child_transform;
  btTransform pre_transform = child_transform;
  if (compound.m_preTransform) pre_transform = pre_transform * *compound.m_preTransform;
  const btCollisionObjectWrapper wrapper(&compound, child_shape, compound.getCollisionObject(), child_pose,
                                        pre_transform, -1, child.index);
  if (!algorithm) {
    algorithm = children_[child.index] =
        m_dispatcher->findAlgorithm(&wrapper, &plane, shared_manifold_, BT_CONTACT_POINT_ALGORITHMS);
    if (!readyToMeet(child, *algorithm, meeting)) return;
  }
  const bool compound_is_0 = result.getBody0Internal() == compound.getCollisionObject();
  const btCollisionObjectWrapper* replaced = compound_is_0 ? result.getBody0Wrap() : result.getBody1Wrap();
  if (compound_is_0) {
    result.setBody0Wrap(&wrapper);
    result.setShapeIdentifiersA(-1, child.index);
  } else {
    result.setBody1Wrap(&wrapper);
    result.setShapeIdentifiersB(-1, child.index);
  }
  algorithm->processCollision(&wrapper, &plane, meeting.info, &result);
  if (compound_is_0) {
    result.setBody0Wrap(replaced);
  } else {
    result.setBody1Wrap(replaced);
  }
}

void CompoundPlaneAlgorithm::getAllContactManifolds(btManifoldArray& manifolds) {
  for (btCollisionAlgorithm* child : children_) {
    if (child) child->getAllContactManifolds(manifolds);
  }
}

btCollisionAlgorithm* CompoundPlaneAlgorithm::CreateFunc::CreateCollisionAlgorithm(
    btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* body0,
    const btCollisionObjectWrapper* body1) {
  const btCollisionObjectWrapper& compound = *(m_swapped ? body1 : body0);
  if (!compoundOf(compound).getDynamicAabbTree())
    return bullet_fallback->CreateCollisionAlgorithm(info, body0, body1);
  // The dispatcher's pool holds blocks as large as Bullet's compound algorithm.
  static_assert(sizeof(CompoundPlaneAlgorithm) <= sizeof(btCompoundCollisionAlgorithm));
  void* memory = info.m_dispatcher1->allocateCollisionAlgorithm(sizeof(CompoundPlaneAlgorithm));
  return new (memory) CompoundPlaneAlgorithm(info, body0, body1, m_swapped, skips_far_children);
}

void CompoundPlaneAlgorithm::registerWith(btCollisionDispatcher& dispatcher,
                                          btCollisionConfiguration& configuration, CreateFunc& compound_first,
                                          CreateFunc& plane_first) {
  const auto* convex_plane = dynamic_cast<const btConvexPlaneCollisionAlgorithm::CreateFunc*>(
      configuration.getCollisionAlgorithmCreateFunc(BOX_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE));
  const bool no_perturbation = convex_plane && convex_plane->m_minimumPointsPerturbationThreshold <= 0;
  for (CreateFunc* create : {&compound_first, &plane_first}) {
    create->m_swapped = create == &plane_first;
    create->skips_far_children = no_perturbation;
  }
  compound_first.bullet_fallback =
      configuration.getCollisionAlgorithmCreateFunc(COMPOUND_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE);
  plane_first.bullet_fallback =
      configuration.getCollisionAlgorithmCreateFunc(STATIC_PLANE_PROXYTYPE, COMPOUND_SHAPE_PROXYTYPE);
  dispatcher.registerCollisionCreateFunc(COMPOUND_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE, &compound_first);
  dispatcher.registerCollisionCreateFunc(STATIC_PLANE_PROXYTYPE, COMPOUND_SHAPE_PROXYTYPE, &plane_first);
}

}  // namespace bullet_sim
