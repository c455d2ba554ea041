// Simulation islands: which bodies Bullet solves together, and how each group is solved.
#pragma once

#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <BulletDynamics/Featherstone/btMultiBodyInplaceSolverIslandCallback.h>

namespace bullet_sim {

/// Bullet joins into one simulation island the bodies whose bounds overlap; ODE (Gazebo) those in contact.
/// Joined by contacts, a body at rest beside a robot sleeps instead of waking whenever the robot passes.
class TouchingIslands : public btSimulationIslandManager {
 public:
  void updateActivationState(btCollisionWorld* world, btDispatcher* dispatcher) override;
};

/// Bullet solves every awake island, one without contacts or joints too, where all the solver does is add
/// each rigid body's forces, torques and gyroscopic impulse to its velocities, through its setup and
/// write-back: half of a lone raycast robot's solve. This does that arithmetic directly, in Bullet's
/// order (btSequentialImpulseConstraintSolver's initSolverBody, convertBodies and writeBackBodies), so that
/// every velocity comes out bit for bit as Bullet's. The other islands are batched and solved as before.
class FreeIslandsDirect : public MultiBodyInplaceSolverIslandCallback {
 public:
  using MultiBodyInplaceSolverIslandCallback::MultiBodyInplaceSolverIslandCallback;

  void processIsland(btCollisionObject** bodies, int count, btPersistentManifold** manifolds,
                     int manifold_count, int island) override;
  /// Bullet solves the last batch even when it is empty, as it is once every island was free.
  void processConstraints(int island) override;

 private:
  /// Rigid bodies with mass whose gyroscopic term is the default one: no multibody link, which the
  /// multibody solver steps, and so no multibody constraint either.
  static bool allFree(btCollisionObject** bodies, int count);
  static void applyForces(btRigidBody& body, btScalar dt);
};

}  // namespace bullet_sim
