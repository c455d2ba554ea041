// The Bullet dynamics world: gravity, the fixed step, the solver, and the static geometry of a world spec.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "bullet_sim/model/world.h"

class btCollisionObject;
class btCollisionShape;
class btMultiBodyDynamicsWorld;
class btTransform;

namespace bullet_sim {

class BulletShapes;
struct CollisionNames;
class WorkPool;

struct PhysicsOptions {
  double step_size = 0.001;  ///< [s] every step advances exactly this much
  /// Constraint solver iterations per step, at most: the solve stops once an iteration changes the impulses
  /// by less than `solver_residual`. 10 kept a 33 kg wheelchair within 2 mm of its arc in the prototype
  /// (research/prototype-facts.md), but left the wheelchair on free swivel casters a residual that rolled it
  /// 1.7 mm in 10 s; up to 20, stopping at the residual, hold it within 0.03 mm and take 15 % less time
  /// while it drives, since most steps converge well within 10.
  int solver_iterations = 20;
  /// [(N s)^2] the sum of the squared impulse changes of an iteration below which the solve has converged
  /// (Bullet's least-squares residual threshold).
  double solver_residual = 1e-14;
  /// [m/s] at most, the speed at which contacts push penetrating bodies apart (ODE's contact correcting
  /// velocity). Bullet's solver pushes at erp * depth / dt and the body keeps that speed: 80 m/s for a
  /// robot spawned 10 cm under the ground. Gazebo caps each contact at its surfaces' max_vel (0.01 m/s
  /// unless a <maxVel> says otherwise), which would take 10 s to lift that robot; 0.1 m/s (TurtleBot3's
  /// <maxVel>) lifts it in 1 s and leaves it a hop of v^2 / 2g = 0.5 mm.
  double max_correcting_velocity = 0.1;
};

class PhysicsWorld {
 public:
  /// Adds the static models of `world` as static geometry; its other models are bodies for the caller to add.
  PhysicsWorld(const WorldSpec& world, const PhysicsOptions& options);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  /// Advances exactly one step of options.step_size, cut into substeps() equal substeps; before each,
  /// `before_substep` gets its length [s] (the robots apply their forces again: Bullet clears them).
  void step(const std::function<void(double substep)>& before_substep);
  /// Cuts each step into the fewest equal substeps no longer than `longest` [s] (its robots' shortest
  /// SubstepLimit); infinity leaves steps whole.
  void setLongestSubstep(double longest);
  int substeps() const { return substeps_; }
  double substep() const { return options_.step_size / substeps_; }  ///< [s]
  /// Solves each step's simulation islands (bodies in contact) side by side on `pool`'s threads and the
  /// caller's, when they hold enough contacts to be worth it; nullptr: on the caller's alone. The results are
  /// the same to the last bit either way. `pool` must outlive the world or be unset first.
  void shareSolvesWith(WorkPool* pool);
  /// Steps (substeps) whose islands were solved on more than one thread.
  uint64_t sharedSolves() const;
  /// Frees what the solver kept for the contacts of past steps (after a robot is removed: a robot resting on
  /// 3,000 shapes left 6 MB there).
  void releaseMemory();
  /// Drops what contacts remember between steps (the impulses the solver starts from), so that a reset
  /// world runs as it first did.
  void forgetContacts();

  double stepSize() const { return options_.step_size; }
  /// From the next step on; robots must be told the substep too (PhysicsRobot::setStepSize).
  void setStepSize(double step_size);
  Eigen::Vector3d gravity() const;  ///< [m/s^2]
  void setGravity(const Eigen::Vector3d& gravity);
  /// Moves the static geometry of the world spec's model `model` (an index into WorldSpec::models) so that
  /// the model frame is at `pose`.
  void setModelPose(size_t model, const Eigen::Isometry3d& pose);
  btMultiBodyDynamicsWorld& bullet();

 private:
  /// Adds a sleeping static object of `shape` (owned by shapes_) at `pose`, with no collision names yet;
  /// returns its index into statics_.
  size_t addStatic(btCollisionShape* shape, const btTransform& pose);

  struct Engine;  ///< Bullet's collision configuration, dispatcher, broadphase and solver, in creation order
  /// Fits substeps_ to the step and longest_substep_, and tells the solver.
  void fitSubsteps();
  /// Shows each ContactTuner its contacts with the last solve's impulses: one walk over the manifolds for
  /// every robot, before each substep.
  void weighTunedContacts();

  PhysicsOptions options_;
  double longest_substep_ = std::numeric_limits<double>::infinity();  ///< [s]
  int substeps_ = 1;
  std::unique_ptr<Engine> engine_;
  class CappedWorld;  ///< Bullet's world, its contacts' push-out speed capped
  std::unique_ptr<CappedWorld> world_;
  std::unique_ptr<BulletShapes> shapes_;
  std::vector<std::unique_ptr<btCollisionObject>> statics_;
  /// Where a collision of a world model is: static object `object` (an index into statics_), or its
  /// compound's child `child` (-1: the object itself); and its origin in the model frame.
  struct StaticPlacement {
    size_t object;
    int child;
    Eigen::Isometry3d origin;
  };
  std::vector<std::vector<StaticPlacement>> model_statics_;  ///< per world model
  std::vector<std::unique_ptr<CollisionNames>> static_names_;  ///< per static object (by child), for contacts
};

}  // namespace bullet_sim
