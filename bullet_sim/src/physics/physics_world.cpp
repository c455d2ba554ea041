#include "bullet_sim/physics/physics_world.h"

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>

#include <algorithm>

#include "bullet_shapes.h"
#include "physics/contacts.h"
#include "physics/multibody_robot.h"

namespace bullet_sim {

struct PhysicsWorld::Engine {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btMultiBodyConstraintSolver solver;
};

/// Bullet's solver pushes a contact's bodies apart at erp * depth / dt. For the solver only, a contact
/// deeper than `max_correcting_velocity` allows looks that deep; its real depth comes back after the solve.
class PhysicsWorld::CappedWorld : public btMultiBodyDynamicsWorld {
 public:
  CappedWorld(Engine& engine, double max_correcting_velocity)
      : btMultiBodyDynamicsWorld(&engine.dispatcher, &engine.broadphase, &engine.solver, &engine.configuration),
        max_correcting_velocity_(max_correcting_velocity) {}

  void solveConstraints(btContactSolverInfo& info) override {
    // Multibody contacts correct with erp2, rigid bodies with erp or erp2: the larger one bounds both.
    const btScalar erp = std::max(info.m_erp, info.m_erp2);
    const btScalar deepest = -max_correcting_velocity_ * info.m_timeStep / erp - info.m_linearSlop;
    clamped_.clear();
    for (int m = 0; m < getDispatcher()->getNumManifolds(); ++m) {
      btPersistentManifold& manifold = *getDispatcher()->getManifoldByIndexInternal(m);
      for (int p = 0; p < manifold.getNumContacts(); ++p) {
        btManifoldPoint& point = manifold.getContactPoint(p);
        if (point.m_distance1 >= deepest) continue;
        clamped_.emplace_back(&point, point.m_distance1);
        point.m_distance1 = deepest;
      }
    }
    btMultiBodyDynamicsWorld::solveConstraints(info);
    for (const auto& [point, distance] : clamped_) point->m_distance1 = distance;
  }

 private:
  double max_correcting_velocity_;                            ///< [m/s]
  std::vector<std::pair<btManifoldPoint*, btScalar>> clamped_;  ///< and their depths, kept between steps
};

PhysicsWorld::PhysicsWorld(const WorldSpec& world, const PhysicsOptions& options)
    : options_(options), engine_(std::make_unique<Engine>()), shapes_(std::make_unique<BulletShapes>()) {
  world_ = std::make_unique<CappedWorld>(*engine_, options_.max_correcting_velocity);
  world_->setGravity(toBullet(world.gravity));
  btContactSolverInfo& solver = world_->getSolverInfo();
  solver.m_numIterations = options_.solver_iterations;
  // Multibody contacts start each step from the impulses of the last one, in full: a robot resting on four
  // free wheels is statically indeterminate, and a solve begun from zero leaves a residual that rolled it
  // on (a constant push, 2 mm/s^2 on the smartcar).
  solver.m_solverMode |= SOLVER_USE_ARTICULATED_WARMSTARTING;
  solver.m_articulatedWarmstartingFactor = 1.0;
  solver.m_timeStep = options_.step_size;  // robots size their motor impulses from it before the first step

  // One collision object per shape, not per model: a house's walls as one object would put every robot part
  // next to all of them in the broadphase.
  for (const auto& model : world.models) {
    auto& placed = model_statics_.emplace_back();
    if (!model.is_static) continue;  // a body: the simulation adds it
    for (const auto& collision : model.collisions) {
      placed.emplace_back(statics_.size(), collision.origin);
      auto object = std::make_unique<btCollisionObject>();
      object->setCollisionShape(shapes_->make(collision.shape, /*moving=*/false));
      object->setWorldTransform(toBullet(model.pose * collision.origin));
      object->setFriction(1.0);  // Gazebo's default mu
      object->setRestitution(0);
      static_names_.push_back(std::make_unique<CollisionNames>(CollisionNames{{collision.name}}));
      nameCollisions(*object, *static_names_.back());
      world_->addCollisionObject(object.get(), kStaticGroup, kRobotGroup);
      statics_.push_back(std::move(object));
    }
  }
}

PhysicsWorld::~PhysicsWorld() {
  for (auto& object : statics_) world_->removeCollisionObject(object.get());
}

btMultiBodyDynamicsWorld& PhysicsWorld::bullet() { return *world_; }

void PhysicsWorld::step() { world_->stepSimulation(options_.step_size, 0, options_.step_size); }

void PhysicsWorld::forgetContacts() {
  btDispatcher& dispatcher = *world_->getDispatcher();
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) dispatcher.getManifoldByIndexInternal(m)->clearManifold();
}

void PhysicsWorld::setStepSize(double step_size) {
  options_.step_size = step_size;
  world_->getSolverInfo().m_timeStep = step_size;
}

Eigen::Vector3d PhysicsWorld::gravity() const { return fromBullet(world_->getGravity()); }

void PhysicsWorld::setGravity(const Eigen::Vector3d& gravity) { world_->setGravity(toBullet(gravity)); }

void PhysicsWorld::setModelPose(size_t model, const Eigen::Isometry3d& pose) {
  for (const auto& [index, origin] : model_statics_.at(model)) {
    btCollisionObject& object = *statics_[index];
    object.setWorldTransform(toBullet(pose * origin));
    world_->updateSingleAabb(&object);  // the broadphase refreshes only moving objects by itself
  }
}

}  // namespace bullet_sim
