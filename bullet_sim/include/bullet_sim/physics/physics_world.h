// The Bullet dynamics world: gravity, the fixed step, the solver, and the static geometry of a world spec.
#pragma once

#include <memory>
#include <vector>

#include "bullet_sim/description/world_spec.h"

class btCollisionObject;
class btCollisionShape;
class btMultiBodyDynamicsWorld;
class btTransform;

namespace bullet_sim {

class BulletShapes;

struct PhysicsOptions {
  double step_size = 0.001;  ///< [s] every step advances exactly this much
  /// Constraint solver iterations per step. 10 kept a 33 kg wheelchair within 2 mm of its arc in the
  /// prototype (research/prototype-facts.md); more cost time and bought no accuracy.
  int solver_iterations = 10;
};

class PhysicsWorld {
 public:
  PhysicsWorld(const WorldSpec& world, const PhysicsOptions& options);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  /// Advances exactly one step of options.step_size.
  void step();
  /// Frees what the solver kept for the contacts of past steps (after a robot is removed: a robot resting on
  /// 3,000 shapes left 6 MB there).
  void releaseMemory();

  double stepSize() const { return options_.step_size; }
  btMultiBodyDynamicsWorld& bullet() { return *world_; }

 private:
  /// Adds a sleeping static object of `shape` (owned by shapes_) at `pose`.
  void addStatic(btCollisionShape* shape, const btTransform& pose);

  struct Engine;  ///< Bullet's collision configuration, dispatcher, broadphase and solver, in creation order
  PhysicsOptions options_;
  std::unique_ptr<Engine> engine_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_;
  std::unique_ptr<BulletShapes> shapes_;
  std::vector<std::unique_ptr<btCollisionObject>> statics_;
};

}  // namespace bullet_sim
