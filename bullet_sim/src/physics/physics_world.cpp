#include "bullet_sim/physics/physics_world.h"

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "bullet_shapes.h"
#include "physics/contacts.h"
#include "physics/coulomb_solver.h"
#include "physics/compound_plane.h"
#include "physics/cylinder_plane.h"
#include "physics/islands.h"
#include "physics/multibody_robot.h"
#include "physics/sleep.h"

namespace bullet_sim {

namespace {
constexpr double kStaticCell = 10;  // [m] side of the floor's cells whose static primitives share an object
constexpr double kContactCfm = 1e-5;  // see the solver's settings in PhysicsWorld's constructor
constexpr int kMaxSubsteps = 1000;  // per step: a limit so short it would stall the world is not followed
}  // namespace

namespace {
/// Two boxes meet by clipping one's face against the other's (Bullet's convex-convex algorithm over the
/// boxes' faces), keeping the points within reach as well as the touching ones: Bullet's box-box detector
/// keeps only the touching ones, so a robot body a hair off square took a whole strike on its lower edge (and
/// tipped back) before its upper edge touched. A box gets its faces when it first meets another, not at load:
/// 10,000 static boxes took a second more to load.
struct BoxBoxCreateFunc : public btCollisionAlgorithmCreateFunc {
  btCollisionAlgorithmCreateFunc* convex = nullptr;
  btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                 const btCollisionObjectWrapper* body0,
                                                 const btCollisionObjectWrapper* body1) override {
    for (const btCollisionObjectWrapper* body : {body0, body1}) {
      // The shapes are BulletShapes', not const: only the wrapper hands them out as const.
      auto* box = const_cast<btBoxShape*>(static_cast<const btBoxShape*>(body->getCollisionShape()));
      if (!box->getConvexPolyhedron()) box->initializePolyhedralFeatures();
    }
    return convex->CreateCollisionAlgorithm(info, body0, body1);
  }
};
}  // namespace

struct PhysicsWorld::Engine {
  Engine() {
    CylinderPlaneAlgorithm::registerWith(dispatcher, cylinder_plane, plane_cylinder);
    CompoundPlaneAlgorithm::registerWith(dispatcher, configuration, compound_plane, plane_compound);
    box_box.convex = configuration.getCollisionAlgorithmCreateFunc(CONVEX_HULL_SHAPE_PROXYTYPE,
                                                                   CONVEX_HULL_SHAPE_PROXYTYPE);
    dispatcher.registerCollisionCreateFunc(BOX_SHAPE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, &box_box);
  }
  btDefaultCollisionConfiguration configuration;
  CylinderPlaneAlgorithm::CreateFunc cylinder_plane, plane_cylinder;  ///< outlive the dispatcher
  CompoundPlaneAlgorithm::CreateFunc compound_plane, plane_compound;
  BoxBoxCreateFunc box_box;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  /// Its work arrays grow with the contacts of a step and never shrink: releaseMemory() replaces it.
  std::unique_ptr<btMultiBodyConstraintSolver> solver = std::make_unique<CoulombSolver>();
};

namespace {
/// [m/s] how fast two rigid bodies (or one and the static world) close at a contact, before the solve; -1
/// where a multibody link takes part (its velocity is the multibody's to tell).
double approachSpeed(const btManifoldPoint& point, const btCollisionObject& a, const btCollisionObject& b) {
  const btRigidBody* body_a = btRigidBody::upcast(&a);
  const btRigidBody* body_b = btRigidBody::upcast(&b);
  const bool rigid_a = body_a || a.isStaticObject();
  const bool rigid_b = body_b || b.isStaticObject();
  if (!rigid_a || !rigid_b) return -1;
  btVector3 relative(0, 0, 0);
  if (body_a) relative +=
      body_a->getVelocityInLocalPoint(point.getPositionWorldOnA() - body_a->getCenterOfMassPosition());
  if (body_b) relative -=
      body_b->getVelocityInLocalPoint(point.getPositionWorldOnB() - body_b->getCenterOfMassPosition());
  return std::max(0.0, -static_cast<double>(relative.dot(point.m_normalWorldOnB)));
}

/// A contact between two rigid bodies (or one and the static world), closing at `approach`
/// (approachSpeed), whose gap the bodies cannot close in this substep: its solver row would stay at zero
/// impulse. Bullet keeps such points within 2 cm (a raycast wheel's rim hovers 0.5 mm over the ground for as
/// long as its spring holds it), and solving them cost a raycast robot half its step.
bool outOfReach(const btManifoldPoint& point, double approach, double gravity, double dt) {
  return point.m_distance1 > 0 && approach >= 0 && point.m_distance1 > reachableGap(approach, gravity, dt);
}

/// The compliance of the contacts (the solver's constraint force mixing) lets a contact still close, after
/// the solve, at cfm / dt times its impulse, which the correction of its depth must make up:
/// - A body at rest closes at cfm times its weight, and the correction is capped at max_correcting_velocity:
///   a 1e4 kg base on a 2 kg robot's wheels closed at 0.3 m/s on its caster, sank 16 cm (the contact
///   model) or tipped back 40 degrees (raycast), and heavier ones sank metres. The compliance falls with the
///   mass a contact carries above kCompliantMass, so that every robot sags as one of that mass does; within
///   one robot it is the same at every contact, which then share its load as before.
/// - A strike's impulse lets much through, and unevenly. A 37 kg wheelchair (raycast) set moving down at
///   50 m/s onto its four rims kept closing at 4.5 m/s at its front rims, which took 450 N s each, and at
///   1.6 m/s at its rear ones (160 N s): it left the strike pitching at 4.8 rad/s and tipped onto its back. A
///   contact closing faster than kCompliantApproach gets the compliance cut in proportion, so that what it
///   lets through stays what it lets through at this speed (under 0.1 m/s for that wheelchair at 1 ms).
constexpr double kCompliantMass = 200;      // [kg]
constexpr double kCompliantApproach = 1.0;  // [m/s]

/// [kg] the heavier of the two moving things a contact joins (a multibody robot whole), 0 for none.
double carriedMass(const btCollisionObject& a, const btCollisionObject& b) {
  double heaviest = 0;
  for (const btCollisionObject* object : {&a, &b}) {
    if (const btRigidBody* body = btRigidBody::upcast(object)) {
      if (body->getInvMass() > 0) heaviest = std::max(heaviest, 1 / double(body->getInvMass()));
    } else if (const auto* link = btMultiBodyLinkCollider::upcast(object)) {
      double mass = link->m_multiBody->getBaseMass();
      for (int k = 0; k < link->m_multiBody->getNumLinks(); ++k) mass += link->m_multiBody->getLinkMass(k);
      heaviest = std::max(heaviest, mass);
    }
  }
  return heaviest;
}

void limitCompliance(btManifoldPoint& point, double approach, double mass, double cfm) {
  double limited = cfm;
  if (mass > kCompliantMass) limited *= kCompliantMass / mass;
  if (approach > kCompliantApproach) limited *= kCompliantApproach / approach;
  if (limited < cfm) {
    point.m_contactCFM = static_cast<btScalar>(limited);
    point.m_contactPointFlags |= BT_CONTACT_FLAG_HAS_CONTACT_CFM;
  } else {
    point.m_contactPointFlags &= ~BT_CONTACT_FLAG_HAS_CONTACT_CFM;
  }
}
}  // namespace

/// Bullet's solver pushes a contact's bodies apart at erp * depth / dt. For the solver only, a contact
/// deeper than `max_correcting_velocity` allows looks that deep; its real depth comes back after the solve.
/// A contact out of reach (outOfReach) looks farther than any solver row reaches, and carries no impulse.
class PhysicsWorld::CappedWorld : public btMultiBodyDynamicsWorld {
 public:
  CappedWorld(Engine& engine, double max_correcting_velocity)
      : btMultiBodyDynamicsWorld(&engine.dispatcher, &engine.broadphase, engine.solver.get(),
                                 &engine.configuration),
        max_correcting_velocity_(max_correcting_velocity) {
    m_islandManager->~btSimulationIslandManager();
    btAlignedFree(m_islandManager);
    m_islandManager = new (btAlignedAlloc(sizeof(TouchingIslands), 16)) TouchingIslands();
    delete m_solverMultiBodyIslandCallback;  // allocated with new by Bullet, deleted so by its destructor
    m_solverMultiBodyIslandCallback = new IslandSolver(engine.solver.get(), &engine.dispatcher);
  }

  IslandSolver& islands() { return *static_cast<IslandSolver*>(m_solverMultiBodyIslandCallback); }
  WorkPool* pool = nullptr;  ///< shares the islands' solve, if set

  /// Bullet predicts every rigid body's motion each step, asleep or not, and damps it by pow(1 - damping, dt)
  /// even when damping is 0: two hundred sleeping boxes cost 100 k instructions a step. Asleep, a body stays
  /// where it is; undamped, its velocity stays as it is. The prediction serves continuous collision alone,
  /// which no body of ours uses: without it, Bullet also stops widening each body's bounds to where it is
  /// predicted to be (and computing them twice). A body's bounds stay widened by the 2 cm within which
  /// contacts are found, outside which the narrowphase would find no point either. (5 % of ten wheelchairs'
  /// instructions.)
  void predictUnconstraintMotion(btScalar dt) override {
    const bool continuous = usesContinuousCollision();
    getDispatchInfo().m_useContinuous = continuous;
    for (int k = 0; k < m_nonStaticRigidBodies.size(); ++k) {
      btRigidBody& body = *m_nonStaticRigidBodies[k];
      if (body.isStaticOrKinematicObject() || !body.isActive()) continue;
      if (body.getLinearDamping() != 0 || body.getAngularDamping() != 0) body.applyDamping(dt);
      if (continuous) {
        body.predictIntegratedTransform(dt, body.getInterpolationWorldTransform());
      } else {
        body.setInterpolationWorldTransform(body.getWorldTransform());
      }
    }
    predictMultiBodyTransforms(dt);
  }

  // Bullet makes predictive contacts here for continuous collision; without it, all that is left of this is
  // resetting the hit fractions (1 % of ten wheelchairs' step).
  void createPredictiveContacts(btScalar dt) override {
    if (getDispatchInfo().m_useContinuous) {
      btDiscreteDynamicsWorld::createPredictiveContacts(dt);
      return;
    }
    releasePredictiveContacts();
    for (int k = 0; k < m_nonStaticRigidBodies.size(); ++k) m_nonStaticRigidBodies[k]->setHitFraction(1);
  }

  void solveConstraints(btContactSolverInfo& info) override {
    // Multibody contacts correct with erp2, rigid bodies with erp or erp2: the larger one bounds both.
    const btScalar erp = std::max(info.m_erp, info.m_erp2);
    const btScalar deepest = -max_correcting_velocity_ * info.m_timeStep / erp - info.m_linearSlop;
    const double gravity = getGravity().length();
    moved_.clear();
    for (int m = 0; m < getDispatcher()->getNumManifolds(); ++m) {
      btPersistentManifold& manifold = *getDispatcher()->getManifoldByIndexInternal(m);
      ContactTuner* tuner_a = tunerOf(*manifold.getBody0());
      ContactTuner* tuner_b = tunerOf(*manifold.getBody1());
      const double carried = carriedMass(*manifold.getBody0(), *manifold.getBody1());
      for (int p = 0; p < manifold.getNumContacts(); ++p) {
        btManifoldPoint& point = manifold.getContactPoint(p);
        const double approach = approachSpeed(point, *manifold.getBody0(), *manifold.getBody1());
        limitCompliance(point, approach, carried, info.m_globalCfm);
        if (outOfReach(point, approach, gravity, info.m_timeStep)) {
          hide(point, manifold.getContactProcessingThreshold());
          continue;
        }
        point.m_combinedFriction =
            contactFriction(*manifold.getBody0(), point.m_index0, *manifold.getBody1(), point.m_index1);
        // Two robots' rims that meet both move the point's friction: B adds to what A set, whatever their
        // order (B overwriting A let the robot spawned first push the other back at full speed, head-on).
        const bool tuned = tuner_a && tuner_a->tune(point, point.m_index0, /*ours_is_a=*/true, false);
        if (tuner_b) tuner_b->tune(point, point.m_index1, /*ours_is_a=*/false, tuned);
        if (point.m_distance1 >= deepest) continue;
        moved_.emplace_back(&point, point.m_distance1);
        point.m_distance1 = deepest;
      }
    }
    // btMultiBodyDynamicsWorld::solveConstraints, with the islands built and solved by IslandSolver: Bullet's
    // last batch is then empty, and what is left is the multibodies' velocities.
    solveExternalForces(info);
    WorkPool* sharing = pool && onlyIslandsApart() ? pool : nullptr;
    islands().buildAndSolve(sharing, getNumCollisionObjects() + 1, [this] { buildIslands(); });
    solveInternalConstraints(info);
    for (const auto& [point, distance] : moved_) point->m_distance1 = distance;
  }

 private:
  /// Whether islands share no state in Bullet's solver: no typed constraint (none of ours; not vetted) and no
  /// kinematic rigid body, which joins no island and gets a solver body in each island it touches, through
  /// its one companion id (Bullet built without BT_THREADSAFE). bullet_sim makes neither.
  bool onlyIslandsApart() const {
    if (getNumConstraints() > 0) return false;
    for (int k = 0; k < m_nonStaticRigidBodies.size(); ++k) {
      if (m_nonStaticRigidBodies[k]->isKinematicObject()) return false;
    }
    return true;
  }

  bool usesContinuousCollision() const {
    for (int k = 0; k < m_nonStaticRigidBodies.size(); ++k) {
      if (m_nonStaticRigidBodies[k]->getCcdSquareMotionThreshold() != 0) return true;
    }
    return false;
  }

  void hide(btManifoldPoint& point, btScalar processing_threshold) {
    moved_.emplace_back(&point, point.m_distance1);
    point.m_distance1 = std::max(processing_threshold, btScalar(0)) * 2 + 1;
    point.m_appliedImpulse = point.m_appliedImpulseLateral1 = point.m_appliedImpulseLateral2 = 0;
  }

  double max_correcting_velocity_;                            ///< [m/s]
  std::vector<std::pair<btManifoldPoint*, btScalar>> moved_;  ///< and their distances, kept between steps
};

PhysicsWorld::PhysicsWorld(const WorldSpec& world, const PhysicsOptions& options)
    : options_(options), engine_(std::make_unique<Engine>()), shapes_(std::make_unique<BulletShapes>()) {
  world_ = std::make_unique<CappedWorld>(*engine_, options_.max_correcting_velocity);
  world_->setGravity(toBullet(world.gravity));
  btContactSolverInfo& solver = world_->getSolverInfo();
  solver.m_numIterations = options_.solver_iterations;
  // A robot on four or more rigid wheels is statically indeterminate: with rigid contacts the solver may
  // carry it on one diagonal, and a skid-steer robot then turned at half of Coulomb's rate. A little
  // compliance (ODE's default constraint force mixing, 1e-5) shares the load as tyres do; it sinks a 140 kg
  // robot by less than 0.1 mm.
  solver.m_globalCfm = kContactCfm;
  solver.m_leastSquaresResidualThreshold = options_.solver_residual;
  // Multibody contacts start each step from the impulses of the last one, in full: a robot resting on four
  // free wheels is statically indeterminate, and a solve begun from zero leaves a residual that rolled it
  // on (a constant push, 2 mm/s^2 on the smartcar).
  solver.m_solverMode |= SOLVER_USE_ARTICULATED_WARMSTARTING;
  solver.m_articulatedWarmstartingFactor = 1.0;
  // So do rigid bodies' (Bullet's default starts them from 85 %): a box at rest then converges in one
  // iteration, not the full 20, until it sleeps (sleeping_test). The first second of bench's 20 wheelchairs
  // in walled_boxes.world, its 200 boxes awake and resting, took 19.3 G instructions before, 3.9 G after.
  solver.m_warmstartingFactor = 1.0;
  // Contacts a ContactTuner gave friction directions (a raycast wheel's rim) keep them.
  solver.m_solverMode |= SOLVER_ENABLE_FRICTION_DIRECTION_CACHING;
  solver.m_timeStep = options_.step_size;  // robots size their motor impulses from it before the first step
  // Bullet's rigid bodies sleep after this long at rest: one global (2 s unless set), Gazebo's 1 s.
  gDeactivationTime = kSleepTime;

  // Bullet walks every collision object each step (10,000 boxes as as many objects took most of a step), so
  // primitives share one compound per cell of the floor, whose own tree finds the few a robot touches; a cell
  // rather than the whole world, lest every robot part overlap one giant object in the broadphase. Planes and
  // triangle meshes stay objects of their own. Static objects sleep: Bullet then leaves their bounds alone.
  world_->setForceUpdateAllAabbs(false);
  std::map<std::pair<long, long>, size_t> cells;  // a cell's compound object, as an index into statics_
  for (const auto& model : world.models) {
    auto& placed = model_statics_.emplace_back();
    if (!model.is_static) continue;  // a body: the simulation adds it
    for (const auto& collision : model.collisions) {
      const btTransform pose = toBullet(model.pose * collision.origin);
      btCollisionShape* shape = shapes_->make(collision.shape, /*moving=*/false);
      const Shape::Type type = collision.shape.type;
      if (type == Shape::Type::kPlane || type == Shape::Type::kMesh) {
        placed.push_back({addStatic(shape, pose), -1, collision.origin});
        static_names_.back()->names.push_back(collision.name);
        static_names_.back()->mu.push_back(collision.mu);
        continue;
      }
      const Eigen::Vector2d cell = (fromBullet(pose.getOrigin()).head<2>() / kStaticCell).array().floor();
      const auto [found, added] =
          cells.try_emplace({static_cast<long>(cell.x()), static_cast<long>(cell.y())}, statics_.size());
      if (added) addStatic(shapes_->makeCompound(), btTransform::getIdentity());  // bounds once filled
      btCollisionObject& object = *statics_[found->second];
      auto& compound = static_cast<btCompoundShape&>(*object.getCollisionShape());
      compound.addChildShape(pose, shape);
      static_names_[found->second]->names.push_back(collision.name);
      static_names_[found->second]->mu.push_back(collision.mu);
      placed.push_back({found->second, compound.getNumChildShapes() - 1, collision.origin});
    }
  }
  for (const auto& [cell, index] : cells) world_->updateSingleAabb(statics_[index].get());
}

size_t PhysicsWorld::addStatic(btCollisionShape* shape, const btTransform& pose) {
  auto object = std::make_unique<btCollisionObject>();
  object->setCollisionShape(shape);
  object->setWorldTransform(pose);
  object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
  object->setActivationState(ISLAND_SLEEPING);
  object->setRestitution(0);
  static_names_.push_back(std::make_unique<CollisionNames>());
  nameCollisions(*object, *static_names_.back());
  world_->addCollisionObject(object.get(), kStaticGroup, kRobotGroup);
  statics_.push_back(std::move(object));
  return statics_.size() - 1;
}

PhysicsWorld::~PhysicsWorld() {
  for (auto& object : statics_) world_->removeCollisionObject(object.get());
}

void PhysicsWorld::releaseMemory() {
  auto fresh = std::make_unique<CoulombSolver>();
  world_->setMultiBodyConstraintSolver(fresh.get());  // keeps the world's solver settings
  engine_->solver = std::move(fresh);
  world_->islands().releaseHelpers();
}

btMultiBodyDynamicsWorld& PhysicsWorld::bullet() { return *world_; }

void PhysicsWorld::shareSolvesWith(WorkPool* pool) { world_->pool = pool; }

uint64_t PhysicsWorld::sharedSolves() const { return world_->islands().sharedSolves(); }

void PhysicsWorld::step(const std::function<void(double substep)>& before_substep) {
  const double substep = this->substep();
  for (int s = 0; s < substeps_; ++s) {
    weighTunedContacts();
    before_substep(substep);
    world_->stepSimulation(substep, 0, substep);
  }
}

void PhysicsWorld::weighTunedContacts() {
  btDispatcher& dispatcher = *world_->getDispatcher();
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
    ContactTuner* tuner_a = tunerOf(*manifold.getBody0());
    ContactTuner* tuner_b = tunerOf(*manifold.getBody1());
    if (!tuner_a && !tuner_b) continue;
    for (int p = 0; p < manifold.getNumContacts(); ++p) {
      const btManifoldPoint& point = manifold.getContactPoint(p);
      if (tuner_a) tuner_a->weigh(point, point.m_index0);
      if (tuner_b) tuner_b->weigh(point, point.m_index1);
    }
  }
}

void PhysicsWorld::setLongestSubstep(double longest) {
  longest_substep_ = longest;
  fitSubsteps();
}

void PhysicsWorld::fitSubsteps() {
  // A hair of slack: a limit that divides the step exactly (1 ms into a 10 ms step) gives that many.
  const double count = std::ceil(options_.step_size / longest_substep_ * (1 - 1e-9));
  substeps_ = std::isfinite(count) ? static_cast<int>(std::clamp(count, 1.0, double(kMaxSubsteps))) : 1;
  world_->getSolverInfo().m_timeStep = substep();
}

void PhysicsWorld::forgetContacts() {
  btDispatcher& dispatcher = *world_->getDispatcher();
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m)
    dispatcher.getManifoldByIndexInternal(m)->clearManifold();
}

void PhysicsWorld::setStepSize(double step_size) {
  options_.step_size = step_size;
  fitSubsteps();
}

Eigen::Vector3d PhysicsWorld::gravity() const { return fromBullet(world_->getGravity()); }

void PhysicsWorld::setGravity(const Eigen::Vector3d& gravity) {
  wakeSleepers(*world_);  // first: Bullet gives the new gravity only to bodies awake
  world_->setGravity(toBullet(gravity));
}

void PhysicsWorld::setModelPose(size_t model, const Eigen::Isometry3d& pose) {
  std::vector<btCollisionObject*> moved;
  for (const auto& placement : model_statics_.at(model)) {
    btCollisionObject& object = *statics_[placement.object];
    const btTransform transform = toBullet(pose * placement.origin);
    if (placement.child < 0) {
      object.setWorldTransform(transform);
    } else {  // its cell's bounds are recomputed once below
      static_cast<btCompoundShape*>(object.getCollisionShape())
          ->updateChildTransform(placement.child, transform, false);
    }
    if (std::find(moved.begin(), moved.end(), &object) == moved.end()) moved.push_back(&object);
  }
  for (btCollisionObject* object : moved) {
    if (auto* compound = dynamic_cast<btCompoundShape*>(object->getCollisionShape()))
      compound->recalculateLocalAabb();
    world_->updateSingleAabb(object);  // the broadphase refreshes only moving objects by itself
  }
  wakeTouching(*world_, {moved.begin(), moved.end()});  // what rested on the model's old place falls
}

}  // namespace bullet_sim
