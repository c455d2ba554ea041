#include "physics/islands.h"

#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <thread>

#include "common/work_pool.h"
#include "physics/coulomb_solver.h"

namespace bullet_sim {

namespace {
/// What a step's solve costs, counted in rigid contact points: on this project's 2-core VM a box's point
/// costs the solver about 0.6 us, a multibody's about 5 us (its rows span the robot's joints). Waking the
/// pool's other thread and joining it costs some 30 us, so a solve is shared from about 40 us of work.
constexpr int kMultiBodyPointCost = 8;
constexpr int kCostWorthSharing = 64;

template <typename T>
void copy(const btAlignedObjectArray<T>& from, std::vector<T>& to) {
  to.clear();
  for (int k = 0; k < from.size(); ++k) to.push_back(from[k]);
}
}  // namespace

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

IslandSolver::IslandSolver(btMultiBodyConstraintSolver* solver, btDispatcher* dispatcher)
    : MultiBodyInplaceSolverIslandCallback(solver, dispatcher) {}

IslandSolver::~IslandSolver() = default;

void IslandSolver::processIsland(btCollisionObject** bodies, int count, btPersistentManifold** manifolds,
                                 int manifold_count, int island) {
  touching_.clear();
  for (int m = 0; m < manifold_count; ++m) {
    if (manifolds[m]->getNumContacts() == 0) continue;
    touching_.push_back(manifolds[m]);
    const bool multibody = btMultiBodyLinkCollider::upcast(manifolds[m]->getBody0()) ||
                           btMultiBodyLinkCollider::upcast(manifolds[m]->getBody1());
    queued_cost_ += manifolds[m]->getNumContacts() * (multibody ? kMultiBodyPointCost : 1);
  }
  const int touching = static_cast<int>(touching_.size());
  if (island < 0 || touching > 0 || m_numConstraints > 0 || !allFree(bodies, count)) {
    MultiBodyInplaceSolverIslandCallback::processIsland(bodies, count, touching_.data(), touching, island);
    processConstraints(island);  // each island on its own, whatever Bullet's batch size
    return;
  }
  for (int k = 0; k < count; ++k) applyForces(*btRigidBody::upcast(bodies[k]), m_solverInfo->m_timeStep);
}

void IslandSolver::processConstraints(int /*island*/) {
  if (m_bodies.size() + m_softBodies.size() + m_manifolds.size() + m_constraints.size() +
          m_multiBodyConstraints.size() == 0) {
    return;
  }
  Island& queued = queued_.at(queued_count_);  // an island holds a body: never more than buildAndSolve's most
  copy(m_bodies, queued.bodies);
  copy(m_manifolds, queued.manifolds);
  copy(m_constraints, queued.constraints);
  copy(m_multiBodyConstraints, queued.multibody_constraints);
  m_bodies.resize(0);
  m_softBodies.resize(0);
  m_manifolds.resize(0);
  m_constraints.resize(0);
  m_multiBodyConstraints.resize(0);
  published_.store(++queued_count_, std::memory_order_release);
}

void IslandSolver::buildAndSolve(WorkPool* pool, size_t most, const std::function<void()>& build) {
  // Sized for the step before it starts: the solving threads read islands while more are queued.
  if (queued_.size() < most) queued_.resize(most);
  queued_count_ = 0;
  queued_cost_ = 0;
  published_ = 0;
  next_ = 0;
  built_ = false;
  const size_t threads = pool && share_next_ ? static_cast<size_t>(pool->threads()) : 1;
  while (helpers_.size() + 1 < threads) helpers_.push_back(std::make_unique<CoulombSolver>());
  const auto part = [&](size_t thread) {
    if (thread == 0) {
      // Set even when the build throws, so that the other threads stop waiting and the pool rethrows.
      const struct Built {
        std::atomic<bool>& built;
        ~Built() { built.store(true, std::memory_order_release); }
      } mark{built_};
      build();
    }
    solveAsQueued(thread == 0 ? *m_solver : *helpers_[thread - 1]);
  };
  if (threads > 1) {
    pool->run(threads, part);  // part 0 is handed out first: no thread waits for a build nobody runs
    ++shared_solves_;
  } else {
    part(0);
  }
  share_next_ = pool && pool->threads() > 1 && queued_count_ > 1 && queued_cost_ >= kCostWorthSharing;
}

void IslandSolver::solveAsQueued(btMultiBodyConstraintSolver& solver) {
  for (size_t k = next_++;; k = next_++) {
    while (k >= published_.load(std::memory_order_acquire)) {
      if (built_.load(std::memory_order_acquire) && k >= published_.load(std::memory_order_acquire)) return;
      std::this_thread::yield();
    }
    solve(solver, queued_[k]);
  }
}

void IslandSolver::solve(btMultiBodyConstraintSolver& solver, Island& island) const {
  solver.solveMultiBodyGroup(island.bodies.data(), static_cast<int>(island.bodies.size()),
                             island.manifolds.data(), static_cast<int>(island.manifolds.size()),
                             island.constraints.data(), static_cast<int>(island.constraints.size()),
                             island.multibody_constraints.data(),
                             static_cast<int>(island.multibody_constraints.size()), *m_solverInfo,
                             m_debugDrawer, m_dispatcher);
}

bool IslandSolver::allFree(btCollisionObject** bodies, int count) {
  constexpr int kOtherGyroscopic =
      BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD;
  for (int k = 0; k < count; ++k) {
    const btRigidBody* body = btRigidBody::upcast(bodies[k]);
    if (!body || body->getInvMass() == 0 || (body->getFlags() & kOtherGyroscopic)) return false;
  }
  return true;
}

void IslandSolver::applyForces(btRigidBody& body, btScalar dt) {
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
