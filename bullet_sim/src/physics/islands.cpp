#include "physics/islands.h"

namespace bullet_sim {

void TouchingIslands::updateActivationState(btCollisionWorld* world, btDispatcher* dispatcher) {
  btSimulationIslandManager::updateActivationState(world, dispatcher);  // tags every body
  getUnionFind().reset(getUnionFind().getNumElements());               // forgets the overlaps
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *dispatcher->getManifoldByIndexInternal(m);
    const btCollisionObject& a = *manifold.getBody0();
    const btCollisionObject& b = *manifold.getBody1();
    if (manifold.getNumContacts() > 0 && a.mergesSimulationIslands() && b.mergesSimulationIslands()) {
      getUnionFind().unite(a.getIslandTag(), b.getIslandTag());
    }
  }
}

void FreeIslandsDirect::processIsland(btCollisionObject** bodies, int count, btPersistentManifold** manifolds,
                                      int manifold_count, int island) {
  if (island < 0 || manifold_count > 0 || m_numConstraints > 0 || !allFree(bodies, count)) {
    MultiBodyInplaceSolverIslandCallback::processIsland(bodies, count, manifolds, manifold_count, island);
    return;
  }
  for (int k = 0; k < count; ++k) applyForces(*btRigidBody::upcast(bodies[k]), m_solverInfo->m_timeStep);
}

void FreeIslandsDirect::processConstraints(int island) {
  if (m_bodies.size() + m_softBodies.size() + m_manifolds.size() + m_constraints.size() +
          m_multiBodyConstraints.size() == 0) {
    return;
  }
  MultiBodyInplaceSolverIslandCallback::processConstraints(island);
}

bool FreeIslandsDirect::allFree(btCollisionObject** bodies, int count) {
  constexpr int kOtherGyroscopic =
      BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD;
  for (int k = 0; k < count; ++k) {
    const btRigidBody* body = btRigidBody::upcast(bodies[k]);
    if (!body || body->getInvMass() == 0 || (body->getFlags() & kOtherGyroscopic)) return false;
  }
  return true;
}

void FreeIslandsDirect::applyForces(btRigidBody& body, btScalar dt) {
  const btVector3 force_impulse = body.getTotalForce() * body.getInvMass() * dt;
  btVector3 torque_impulse = body.getTotalTorque() * body.getInvInertiaTensorWorld() * dt;
  if (body.getFlags() & BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY) {
    torque_impulse += body.computeGyroscopicImpulseImplicit_Body(dt);
  }
  // The solver adds its (zero) velocity changes first: -0 becomes +0 there, and so here.
  const btVector3 no_change(0, 0, 0);
  body.setLinearVelocity((body.getLinearVelocity() + no_change) + force_impulse);
  body.setAngularVelocity((body.getAngularVelocity() + no_change) + torque_impulse);
}

}  // namespace bullet_sim
