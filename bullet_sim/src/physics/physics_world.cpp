#include "bullet_sim/physics/physics_world.h"

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>

#include <map>

#include "bullet_shapes.h"
#include "physics/multibody_robot.h"

namespace bullet_sim {

namespace {
constexpr double kStaticCell = 10;  // [m] side of the floor's cells whose static primitives share an object
}

struct PhysicsWorld::Engine {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  /// Its work arrays grow with the contacts of a step and never shrink: releaseMemory() replaces it.
  std::unique_ptr<btMultiBodyConstraintSolver> solver = std::make_unique<btMultiBodyConstraintSolver>();
};

PhysicsWorld::PhysicsWorld(const WorldSpec& world, const PhysicsOptions& options)
    : options_(options), engine_(std::make_unique<Engine>()), shapes_(std::make_unique<BulletShapes>()) {
  world_ = std::make_unique<btMultiBodyDynamicsWorld>(&engine_->dispatcher, &engine_->broadphase,
                                                      engine_->solver.get(), &engine_->configuration);
  world_->setGravity(toBullet(world.gravity));
  btContactSolverInfo& solver = world_->getSolverInfo();
  solver.m_numIterations = options_.solver_iterations;
  solver.m_timeStep = options_.step_size;  // robots size their motor impulses from it before the first step

  // Bullet walks every collision object each step (10,000 boxes as as many objects took most of a step), so
  // primitives share one compound per cell of the floor, whose own tree finds the few a robot touches; a cell
  // rather than the whole world, lest every robot part overlap one giant object in the broadphase. Planes and
  // triangle meshes stay objects of their own. Static objects sleep: Bullet then leaves their bounds alone.
  world_->setForceUpdateAllAabbs(false);
  std::map<std::pair<long, long>, btCompoundShape*> cells;
  for (const auto& model : world.models) {
    for (const auto& collision : model.collisions) {
      const Eigen::Isometry3d pose = model.pose * collision.origin;
      btCollisionShape* shape = shapes_->make(collision.shape, /*moving=*/false);
      const Shape::Type type = collision.shape.type;
      if (type == Shape::Type::kPlane || type == Shape::Type::kMesh) {
        addStatic(shape, toBullet(pose));
        continue;
      }
      const Eigen::Vector2d cell = (pose.translation().head<2>() / kStaticCell).array().floor();
      btCompoundShape*& compound = cells[{static_cast<long>(cell.x()), static_cast<long>(cell.y())}];
      if (!compound) compound = shapes_->makeCompound();
      compound->addChildShape(toBullet(pose), shape);
    }
  }
  for (const auto& [cell, compound] : cells) addStatic(compound, btTransform::getIdentity());
}

void PhysicsWorld::addStatic(btCollisionShape* shape, const btTransform& pose) {
  auto object = std::make_unique<btCollisionObject>();
  object->setCollisionShape(shape);
  object->setWorldTransform(pose);
  object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
  object->setActivationState(ISLAND_SLEEPING);
  object->setFriction(1.0);  // Gazebo's default mu
  object->setRestitution(0);
  world_->addCollisionObject(object.get(), kStaticGroup, kRobotGroup);
  statics_.push_back(std::move(object));
}

PhysicsWorld::~PhysicsWorld() {
  for (auto& object : statics_) world_->removeCollisionObject(object.get());
}

void PhysicsWorld::releaseMemory() {
  auto fresh = std::make_unique<btMultiBodyConstraintSolver>();
  world_->setMultiBodyConstraintSolver(fresh.get());  // keeps the world's solver settings
  engine_->solver = std::move(fresh);
}

void PhysicsWorld::step() { world_->stepSimulation(options_.step_size, 0, options_.step_size); }

}  // namespace bullet_sim
