#include "physics/coulomb_solver.h"

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <initializer_list>

namespace bullet_sim {

namespace {

constexpr btScalar kSlidingSpeed = 1e-4;  ///< [m/s] a slower slip is sticking: its directions stay Bullet's

}  // namespace

void CoulombSolver::convertContacts(btPersistentManifold** manifolds, int count,
                                    const btContactSolverInfo& info) {
  btMultiBodyConstraintSolver::convertContacts(manifolds, count, info);
  if (!(info.m_solverMode & SOLVER_USE_2_FRICTION_DIRECTIONS)) return;  // one row: nothing to turn
  const int rows = m_multiBodyFrictionContactConstraints.size();
  if (rows < 2) return;  // no multibody touches anything: the common raycast-only world
  manifold_of_.clear();
  for (int m = 0; m < count; ++m) {
    for (int p = 0; p < manifolds[m]->getNumContacts(); ++p) {
      manifold_of_[&manifolds[m]->getContactPoint(p)] = manifolds[m];
    }
  }
  for (int first = 0; first + 1 < rows; first += 2) {
    const void* point = m_multiBodyFrictionContactConstraints[first].m_originalContactPoint;
    const auto found = manifold_of_.find(static_cast<const btManifoldPoint*>(point));
    if (found != manifold_of_.end()) alignWithSlip(first, *found->second, info);
  }
}

void CoulombSolver::alignWithSlip(int first, btPersistentManifold& manifold,
                                  const btContactSolverInfo& info) {
  const btMultiBodySolverConstraint& row1 = m_multiBodyFrictionContactConstraints[first];
  const btMultiBodySolverConstraint& row2 = m_multiBodyFrictionContactConstraints[first + 1];
  if (row1.m_frictionIndex != row2.m_frictionIndex ||
      row1.m_originalContactPoint != row2.m_originalContactPoint || row1.m_jacDiagABInv == 0 ||
      row2.m_jacDiagABInv == 0) {
    return;
  }
  btManifoldPoint& point = *static_cast<btManifoldPoint*>(row1.m_originalContactPoint);
  // A friction row's right-hand side is -(relative velocity along its direction) / its effective mass.
  const btVector3 slip = point.m_lateralFrictionDir1 * (-row1.m_rhs / row1.m_jacDiagABInv) +
                         point.m_lateralFrictionDir2 * (-row2.m_rhs / row2.m_jacDiagABInv);
  if (slip.length() < kSlidingSpeed) return;
  point.m_lateralFrictionDir1 = slip.normalized();
  point.m_lateralFrictionDir2 = point.m_normalWorldOnB.cross(point.m_lateralFrictionDir1).normalized();
  // New rows go to the end of the array; they take the old ones' places, which the contact's rows index.
  const int friction_index = row1.m_frictionIndex;
  const int end = m_multiBodyFrictionContactConstraints.size();
  auto* body0 = const_cast<btCollisionObject*>(manifold.getBody0());
  auto* body1 = const_cast<btCollisionObject*>(manifold.getBody1());
  for (const btVector3& direction : {point.m_lateralFrictionDir1, point.m_lateralFrictionDir2}) {
    addMultiBodyFrictionConstraint(direction, 0, &manifold, friction_index, point, body0, body1, info.m_sor,
                                   info);
  }
  m_multiBodyFrictionContactConstraints[first] = m_multiBodyFrictionContactConstraints[end];
  m_multiBodyFrictionContactConstraints[first + 1] = m_multiBodyFrictionContactConstraints[end + 1];
  m_multiBodyFrictionContactConstraints.resize(end);
}

}  // namespace bullet_sim
