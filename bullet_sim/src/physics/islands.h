// Simulation islands: which bodies Bullet solves together, and how each group is solved.
#pragma once

#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <BulletDynamics/Featherstone/btMultiBodyInplaceSolverIslandCallback.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace bullet_sim {

class WorkPool;

/// Bullet joins into one simulation island the bodies whose bounds overlap; ODE (Gazebo) those in contact.
/// Joined by contacts, a body at rest beside a robot sleeps instead of waking whenever the robot passes.
class TouchingIslands : public btSimulationIslandManager {
 public:
  void updateActivationState(btCollisionWorld* world, btDispatcher* dispatcher) override;
};

/// Solves a step's islands, which Bullet hands over one at a time (and would solve in batches of 128 rows):
/// - A free island (rigid bodies that touch nothing, without joints), where all the solver does is add each
///   body's forces, torques and gyroscopic impulse to its velocities through its setup and write-back (half
///   of a lone raycast robot's solve), gets that arithmetic directly, in Bullet's order
///   (btSequentialImpulseConstraintSolver's initSolverBody, convertBodies and writeBackBodies), so that every
///   velocity comes out bit for bit as Bullet's.
/// - Every other island is queued on its own, and buildAndSolve() solves them side by side on the
///   simulation's pool, each thread with a solver of its own. Islands share no body and each solve stops at
///   its own residual, so which thread solves an island never shows: reruns are bit-identical with any
///   threads. (Bullet's one shared write there is a statistics counter, gNumSplitImpulseRecoveries, as in
///   its own multithreaded world.) The caller passes no pool while the world has a kinematic body or a typed
///   constraint: Bullet's solver would share state between islands there.
/// - A manifold without contact points (bounds that overlap, bodies that do not touch) is left out of its
///   island: TouchingIslands did not join its bodies, and Bullet's solver sets up both bodies of every
///   manifold it is given, so the other island's body would have its forces added twice.
class IslandSolver : public MultiBodyInplaceSolverIslandCallback {
 public:
  IslandSolver(btMultiBodyConstraintSolver* solver, btDispatcher* dispatcher);
  ~IslandSolver() override;

  void processIsland(btCollisionObject** bodies, int count, btPersistentManifold** manifolds,
                     int manifold_count, int island) override;
  /// Queues what Bullet collected; nothing when it collected nothing (the last batch, every island free).
  void processConstraints(int island) override;

  /// Builds a step's islands with `build` (Bullet's buildIslands, which hands each to processIsland, at most
  /// `most` of them) and solves them. When the last step's were worth sharing (two or more, with enough
  /// contacts to pay for the handover), on `pool`'s threads: the others solve each island as soon as it is
  /// queued, while the first still builds; else (or with no pool) on the caller's alone.
  void buildAndSolve(WorkPool* pool, size_t most, const std::function<void()>& build);
  /// Solves, since construction, whose islands were shared between threads.
  uint64_t sharedSolves() const { return shared_solves_; }
  /// Drops the other threads' solvers, and the work arrays they kept.
  void releaseHelpers() { helpers_.clear(); }

 private:
  struct Island {
    std::vector<btCollisionObject*> bodies;
    std::vector<btPersistentManifold*> manifolds;
    std::vector<btTypedConstraint*> constraints;
    std::vector<btMultiBodyConstraint*> multibody_constraints;
  };

  /// Rigid bodies with mass whose gyroscopic term is the default one: no multibody link, which the
  /// multibody solver steps, and so no multibody constraint either.
  static bool allFree(btCollisionObject** bodies, int count);
  static void applyForces(btRigidBody& body, btScalar dt);
  void solve(btMultiBodyConstraintSolver& solver, Island& island) const;
  /// Takes the queued islands one at a time and solves them with `solver`, waiting for the next one to be
  /// queued, until every island is built and taken.
  void solveAsQueued(btMultiBodyConstraintSolver& solver);

  std::vector<btPersistentManifold*> touching_;  ///< the island being handed over's manifolds with points
  std::vector<Island> queued_;                   ///< the first queued_count_ are this step's; kept for reuse
  size_t queued_count_ = 0;                      ///< written by the building thread alone
  std::atomic<size_t> published_{0};             ///< queued_count_, for the solving threads
  std::atomic<bool> built_{false};               ///< every island of the step is queued
  std::atomic<size_t> next_{0};                  ///< the next island to take
  int queued_cost_ = 0;  ///< the queued islands' contact points, weighed by what they cost the solver
  bool share_next_ = false;  ///< the last step's solve was worth sharing
  std::vector<std::unique_ptr<btMultiBodyConstraintSolver>> helpers_;  ///< the pool's other threads' solvers
  uint64_t shared_solves_ = 0;
};

}  // namespace bullet_sim
