// Bullet's multibody constraint solver, with each sliding contact's friction along its slip (issue 29).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>

#include <unordered_map>

namespace bullet_sim {

/// Bullet's multibody solver gives a contact two friction rows along directions fixed by its normal alone
/// (btPlaneSpace1; its velocity-dependent direction is commented out for multibodies) and projects their
/// impulses onto the cone by the angle of the impulses it wants, not of the slip. Where the two directions'
/// effective masses differ (a wheel spins freely along one, carries the robot along the other), friction
/// then leans away from the slip: a skid-steer robot turned in place at 0.1 to 0.7 of Coulomb's rate. Here a
/// contact that slides gets its first direction along the slip and its second across it, as Bullet's
/// rigid-body solver does by default: friction opposes the slip at mu N, Coulomb's law.
class CoulombSolver : public btMultiBodyConstraintSolver {
 protected:
  void convertContacts(btPersistentManifold** manifolds, int count, const btContactSolverInfo& info) override;

 private:
  /// Rebuilds the friction rows `first` and `first + 1` along the slip they measure, when it slides.
  void alignWithSlip(int first, btPersistentManifold& manifold, const btContactSolverInfo& info);

  std::unordered_map<const btManifoldPoint*, btPersistentManifold*> manifold_of_;  ///< this solve's points
};

}  // namespace bullet_sim
