#include "bullet_sim/physics/physics_world.h"

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>

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

PhysicsWorld::PhysicsWorld(const WorldSpec& world, const PhysicsOptions& options)
    : options_(options), engine_(std::make_unique<Engine>()), shapes_(std::make_unique<BulletShapes>()) {
  world_ = std::make_unique<btMultiBodyDynamicsWorld>(&engine_->dispatcher, &engine_->broadphase,
                                                      &engine_->solver, &engine_->configuration);
  world_->setGravity(toBullet(world.gravity));
  btContactSolverInfo& solver = world_->getSolverInfo();
  solver.m_numIterations = options_.solver_iterations;
  solver.m_timeStep = options_.step_size;  // robots size their motor impulses from it before the first step

  // One collision object per shape, not per model: a house's walls as one object would put every robot part
  // next to all of them in the broadphase.
  for (const auto& model : world.models) {
    auto& placed = model_statics_.emplace_back();
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

void PhysicsWorld::step() { world_->stepSimulation(options_.step_size, 0, options_.step_size); }

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
