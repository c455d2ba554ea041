// A compound shape against a plane: Bullet's compound algorithm's contacts, without its per-child bounds
// tests.
#pragma once

#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>

#include <vector>

class btCompoundShape;

namespace bullet_sim {

struct WorldPlane;  // physics/cylinder_plane.h

/// Every robot meets the ground plane through its compound shape each substep. Bullet's compound algorithm
/// finds the children near the other shape through the compound's tree and bounds tests, then tests every
/// child's bounds again to free the algorithms of children that left. A plane's bounds are infinite, so every
/// child always passes: this meets every child with the same child algorithms and manifolds, made in the
/// order Bullet's tree first visits them, and leaves the tests out. It also skips a convex child that keeps
/// no point and is beyond reach of the plane (a chassis's seat, its lidar), whose algorithm would find
/// nothing. And it makes no points for a rigid body's convex child that cannot reach the plane within the
/// substep (a raycast wheel's rim, 0.5 mm over the ground while its spring holds it), which the solver would
/// leave without impulse (contacts.h's reachableGap), and drops those it had. Such a rigid body's child
/// skipped either way keeps no algorithm and no manifold until it comes near: the solver, the islands and the
/// contact weighing walk every manifold in the world each step, empty or not. Every other contact is
/// Bullet's, point for point (a rigid body's in manifolds made and freed as its children come and go: in
/// another order). A compound without a tree keeps Bullet's own algorithm, and so do closest-point queries:
/// this is registered for contacts only.
class CompoundPlaneAlgorithm : public btActivatingCollisionAlgorithm {
 public:
  CompoundPlaneAlgorithm(const btCollisionAlgorithmConstructionInfo& info,
                         const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                         bool swapped, bool skips_far_children);
  ~CompoundPlaneAlgorithm() override;

  void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                        const btDispatcherInfo& info, btManifoldResult* result) override;
  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return 1;  // no continuous collision
  }
  void getAllContactManifolds(btManifoldArray& manifolds) override;

  struct CreateFunc : public btCollisionAlgorithmCreateFunc {
    /// Bullet's compound algorithm, for compounds without a tree.
    btCollisionAlgorithmCreateFunc* bullet_fallback = nullptr;
    /// Bullet's convex-plane algorithm queries an empty manifold again with the shape turned about its origin
    /// when multipoint perturbation is on; far children are then never skipped.
    bool skips_far_children = false;
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                   const btCollisionObjectWrapper* body0,
                                                   const btCollisionObjectWrapper* body1) override;
  };

  /// Makes `dispatcher` meet compounds with planes through `compound_first` and `plane_first` (swapped);
  /// `configuration` gives Bullet's own algorithms, for compounds without a tree and for convex children.
  static void registerWith(btCollisionDispatcher& dispatcher, btCollisionConfiguration& configuration,
                           CreateFunc& compound_first, CreateFunc& plane_first);

 private:
  /// A child of the compound, as this meets it.
  struct Child {
    int index;         ///< in the compound
    bool convex;  ///< met by Bullet's convex-plane algorithm or ours for cylinders: one manifold, no state
    btVector3 centre;  ///< of a sphere about it, margin included, in its own frame
    btScalar radius;   ///< taken when the pair is made: a child's shape must not grow after
    /// Its sphere reached the plane when last tested (staysAway): it tests whether it is out of reach first.
    mutable bool sphere_reaches;
  };
  /// Frees the children's algorithms and takes the order of the compound's tree afresh.
  void restart(const btCompoundShape& compound);
  void freeChildren();
  struct Meeting;
  /// Bullet's refresh of the manifolds in manifolds_ that have contacts, before their child is met.
  void refreshManifolds(btManifoldResult& result);
  void processChild(const Child& child, const Meeting& meeting);
  /// Whether the convex child's algorithm would neither add nor refresh a point: it keeps none (its manifolds
  /// in manifolds_), and its sphere stays beyond its manifold's reach of the plane.
  bool beyondReach(const Child& child, const Meeting& meeting) const;
  /// Whether the convex child of a rigid body stays, in this substep, farther from the plane than the body
  /// can close (contacts.h's reachableGap): the solver would give every point it has no impulse.
  bool outOfReach(const Child& child, const Meeting& meeting) const;
  /// Whether the child's sphere stays farther from the plane than a manifold of `breaking_threshold` reaches.
  bool sphereBeyond(const Child& child, const Meeting& meeting, btScalar breaking_threshold) const;
  /// Refreshes the child's own manifolds and tells whether to meet it: not when it is beyond or out of reach,
  /// when a rigid body's child's algorithm and manifold (and the points outOfReach drops) go. A shared
  /// manifold is always met.
  bool readyToMeet(const Child& child, btCollisionAlgorithm& algorithm, const Meeting& meeting);
  /// Whether a rigid body's child without an algorithm is beyond or out of reach: one made now would go
  /// unmet.
  bool staysAway(const Child& child, const Meeting& meeting) const;
  /// Frees the algorithm of the child at `index`, and its manifold.
  void release(int index);

  bool swapped_;  ///< the plane is body 0
  bool skips_far_children_;
  btPersistentManifold* shared_manifold_;
  int revision_ = -1;        ///< of the compound shape, when the order was taken
  std::vector<Child> order_;  ///< in the order Bullet's tree visits them when the pair is made
  std::vector<btCollisionAlgorithm*> children_;  ///< by child index; null while unmet
  /// Of the children's manifolds, once one was made (the same for all: made for the pair's two objects).
  btScalar breaking_threshold_ = -1;
  btManifoldArray manifolds_;                    ///< scratch
};

}  // namespace bullet_sim
