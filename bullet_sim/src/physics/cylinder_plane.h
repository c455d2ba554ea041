// A cylinder against a plane, with the contact points Gazebo's ODE gives it (issue 29).
#pragma once

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>

namespace bullet_sim {

/// A static plane as it lies in the world: its unit normal and a point on it.
struct WorldPlane {
  btVector3 normal;
  btVector3 point;
};
/// The plane of `plane` (a btStaticPlaneShape's object) in the world.
WorldPlane worldPlane(const btCollisionObjectWrapper& plane);

/// Bullet meets a cylinder with a plane at one point, its support point: a wheel lying on the ground touches
/// at one edge of its tread or the other, flipping between them step by step, and a skid-steer robot on such
/// wheels turned at a tenth of Coulomb's rate. This meets it along its tread: at the tread's middle while it
/// lies level, at the middles of its halves once it tilts (ODE's cylinder-plane test touches at both ends),
/// and, standing on an end, at four points of its rim.
class CylinderPlaneAlgorithm : public btCollisionAlgorithm {
 public:
  CylinderPlaneAlgorithm(btPersistentManifold* manifold, const btCollisionAlgorithmConstructionInfo& info,
                         const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                         bool swapped);
  ~CylinderPlaneAlgorithm() override;

  void processCollision(const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1,
                        const btDispatcherInfo& info, btManifoldResult* result) override;
  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return 1;  // no continuous collision
  }
  void getAllContactManifolds(btManifoldArray& manifolds) override;

  struct CreateFunc : public btCollisionAlgorithmCreateFunc {
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                   const btCollisionObjectWrapper* body0,
                                                   const btCollisionObjectWrapper* body1) override;
  };

  /// Makes `dispatcher` meet cylinders with planes through `cylinder_first` and `plane_first` (swapped).
  static void registerWith(btCollisionDispatcher& dispatcher, CreateFunc& cylinder_first,
                           CreateFunc& plane_first);

 private:
  btPersistentManifold* manifold_;
  bool own_manifold_ = false;
  bool swapped_;  ///< the plane is body 0
};

}  // namespace bullet_sim
