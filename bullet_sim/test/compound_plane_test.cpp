// A compound meets a plane with Bullet's own contacts, point for point, each child's in Bullet's order, while
// it sinks, tilts and has children moved, whichever of the two comes first in the pair; a small child far
// from the ground and one lowered to it are met as soon as they come within reach. A rigid body's child that
// cannot reach the plane within the substep has no points, nor a manifold for them.
#include <gtest/gtest.h>

#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <vector>

#include "src/physics/compound_plane.h"
#include "src/physics/cylinder_plane.h"

namespace bullet_sim {
namespace {

constexpr btScalar kLidarHeight = 0.3;  ///< [m] of the lidar's centre above the robot's origin, at first
constexpr int kLidar = 5;                ///< its child index

/// A collision world with the dispatcher the physics world has: ours meets compounds with planes through
/// CompoundPlaneAlgorithm, Bullet's through its own compound algorithm.
struct World {
  explicit World(bool ours) {
    CylinderPlaneAlgorithm::registerWith(dispatcher, cylinder_plane, plane_cylinder);
    if (ours) CompoundPlaneAlgorithm::registerWith(dispatcher, configuration, compound_plane, plane_compound);
  }
  btDefaultCollisionConfiguration configuration;
  CylinderPlaneAlgorithm::CreateFunc cylinder_plane, plane_cylinder;
  CompoundPlaneAlgorithm::CreateFunc compound_plane, plane_compound;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;    // outlive the world, which lets go of them
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};

  btCollisionObject& add(btCollisionShape* shape, const btTransform& pose) {
    objects.push_back(std::make_unique<btCollisionObject>());
    objects.back()->setCollisionShape(shape);
    objects.back()->setWorldTransform(pose);
    world.addCollisionObject(objects.back().get());
    return *objects.back();
  }

  /// A box, a cylinder, a sphere and a hull, side by side under a chassis box; a bolt's head, small enough
  /// that its bounding sphere clears the ground while it is within reach; and a lidar held 0.3 m up.
  btCompoundShape* robot() {
    auto* compound = new btCompoundShape();
    shapes.emplace_back(compound);
    shapes.emplace_back(new btBoxShape(btVector3(0.3, 0.2, 0.1)));
    compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.3)),
                            shapes.back().get());
    shapes.emplace_back(new btCylinderShape(btVector3(0.1, 0.03, 0.1)));  // along y: a wheel
    compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(0.2, 0.25, 0.1)),
                            shapes.back().get());
    shapes.emplace_back(new btSphereShape(0.05));
    compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(-0.25, 0, 0.05)),
                            shapes.back().get());
    const btScalar hull[] = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1};
    shapes.emplace_back(new btConvexHullShape(hull, 4, 3 * sizeof(btScalar)));
    compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(0.2, -0.25, 0.02)),
                            shapes.back().get());
    shapes.emplace_back(new btSphereShape(0.003));
    compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(-0.1, 0.1, 0.013)),
                            shapes.back().get());
    shapes.emplace_back(new btCylinderShapeZ(btVector3(0.04, 0.04, 0.03)));
    compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(0, -0.1, kLidarHeight)),
                            shapes.back().get());
    return compound;
  }

  /// One robot before the ground (the plane is body 1 of its pair) and one after it (body 0).
  World& populate() {
    add(robot(), btTransform::getIdentity());
    shapes.emplace_back(new btStaticPlaneShape(btVector3(0, 0, 1), 0));
    add(shapes.back().get(), btTransform::getIdentity());
    add(robot(), btTransform::getIdentity());
    return *this;
  }

  /// Frame k of the robots' motion: they sink from 3 cm above the ground to 2 cm into it while they tilt.
  void pose(int frame) {
    const btScalar height = 0.03 - 0.001 * frame;
    const btQuaternion tilt(btVector3(1, 0.5, 0).normalized(), 0.004 * frame);
    objects[0]->setWorldTransform(btTransform(tilt, btVector3(0, 0, height)));
    objects[2]->setWorldTransform(btTransform(tilt.inverse(), btVector3(3, 0, height)));
    auto* compound = static_cast<btCompoundShape*>(objects[0]->getCollisionShape());
    if (frame == 25) {  // steering: the wheel turns on the first robot, as a raycast robot's rims do
      compound->updateChildTransform(
          1, btTransform(btQuaternion(btVector3(0, 0, 1), 0.3), btVector3(0.2, 0.25, 0.1)));
    }
    // A kinematic joint lowers the lidar to the ground over frames 10 to 30, without a new revision.
    const btScalar lowered = frame < 10 ? 0 : std::min<btScalar>(1, (frame - 10) / 20.0);
    compound->updateChildTransform(
        kLidar,
        btTransform(btQuaternion::getIdentity(), btVector3(0, -0.1, kLidarHeight * (1 - lowered) + 0.01)));
  }
};

/// A world's contact points, by the manifold's two objects (their indices in World::objects) and the
/// children that touch, each manifold's in its own order.
using Touches = std::map<std::array<int, 4>, std::vector<const btManifoldPoint*>>;

Touches touches(const World& world) {
  const auto index = [&](const btCollisionObject* object) {
    return static_cast<int>(std::find_if(world.objects.begin(), world.objects.end(),
                                         [&](const auto& o) { return o.get() == object; }) -
                            world.objects.begin());
  };
  Touches found;
  for (int m = 0; m < world.dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *world.dispatcher.getManifoldByIndexInternal(m);
    for (int p = 0; p < manifold.getNumContacts(); ++p) {
      const btManifoldPoint& point = manifold.getContactPoint(p);
      found[{index(manifold.getBody0()), index(manifold.getBody1()), point.m_index0, point.m_index1}]
          .push_back(&point);
    }
  }
  return found;
}

TEST(CompoundPlane, MeetsAPlaneWithBulletsContactsPointForPoint) {
  World bullets(false), ours(true);
  bullets.populate();
  ours.populate();
  int points = 0;
  for (int frame = 0; frame < 50; ++frame) {
    for (World* world : {&bullets, &ours}) {
      world->pose(frame);
      world->world.performDiscreteCollisionDetection();
    }
    const Touches expected = touches(bullets), actual = touches(ours);
    ASSERT_EQ(expected.size(), actual.size()) << "frame " << frame;
    for (const auto& [key, want_points] : expected) {
      ASSERT_EQ(actual.count(key), 1u) << "frame " << frame << ", child " << key[2] << "/" << key[3];
      const auto& got_points = actual.at(key);
      ASSERT_EQ(want_points.size(), got_points.size()) << "frame " << frame;
      for (size_t p = 0; p < want_points.size(); ++p, ++points) {
        const btManifoldPoint& want = *want_points[p];
        const btManifoldPoint& got = *got_points[p];
        EXPECT_EQ(want.m_positionWorldOnB, got.m_positionWorldOnB) << "frame " << frame;
        EXPECT_EQ(want.m_normalWorldOnB, got.m_normalWorldOnB) << "frame " << frame;
        EXPECT_EQ(want.m_distance1, got.m_distance1) << "frame " << frame;
      }
    }
  }
  EXPECT_GT(points, 200);  // every child came within reach, most of them for many frames
}

TEST(CompoundPlane, IsWhatTheDispatcherPicksForACompoundOnAPlane) {
  World ours(true);
  ours.populate().pose(0);
  ours.world.performDiscreteCollisionDetection();
  btBroadphasePairArray& pairs = ours.broadphase.getOverlappingPairCache()->getOverlappingPairArray();
  ASSERT_EQ(pairs.size(), 2);  // each robot with the ground; the robots are 3 m apart
  for (int k = 0; k < pairs.size(); ++k)
    EXPECT_NE(dynamic_cast<CompoundPlaneAlgorithm*>(pairs[k].m_algorithm), nullptr);

  World bullets(false);
  bullets.populate().pose(0);
  bullets.world.performDiscreteCollisionDetection();
  btBroadphasePairArray& theirs = bullets.broadphase.getOverlappingPairCache()->getOverlappingPairArray();
  ASSERT_EQ(theirs.size(), 2);
  for (int k = 0; k < theirs.size(); ++k)
    EXPECT_EQ(dynamic_cast<CompoundPlaneAlgorithm*>(theirs[k].m_algorithm), nullptr);
}

/// A rigid body on a wheel (a cylinder 0.1 m in radius, laid on its side as a URDF wheel is) whose rim hovers
/// `gap` over the ground, as a raycast robot's rim does while its spring holds it.
btRigidBody& hoveringWheel(World& world, btScalar gap) {
  auto* compound = new btCompoundShape();
  world.shapes.emplace_back(compound);
  world.shapes.emplace_back(new btCylinderShapeZ(btVector3(0.1, 0.1, 0.03)));
  compound->addChildShape(btTransform(btQuaternion(btVector3(1, 0, 0), SIMD_HALF_PI)),
                          world.shapes.back().get());
  auto* body = new btRigidBody(1.0, nullptr, compound, btVector3(0.01, 0.01, 0.01));
  world.objects.emplace_back(body);
  body->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.1 + gap)));
  body->setGravity(btVector3(0, 0, -9.81));
  world.world.addCollisionObject(body);
  world.shapes.emplace_back(new btStaticPlaneShape(btVector3(0, 0, 1), 0));
  world.add(world.shapes.back().get(), btTransform::getIdentity());
  world.world.getDispatchInfo().m_timeStep = 0.001;
  return *body;
}

int wheelPoints(World& world) {
  int points = 0;
  for (int m = 0; m < world.dispatcher.getNumManifolds(); ++m)
    points += world.dispatcher.getManifoldByIndexInternal(m)->getNumContacts();
  return points;
}

TEST(CompoundPlane, MakesNoPointsForAChildThatCannotReachThePlaneThisSubstep) {
  constexpr btScalar kGap = 0.0005;  // [m] closed within 1 ms only from about 0.3 m/s (contacts.h)
  World bullets(false), ours(true);
  btRigidBody& theirs = hoveringWheel(bullets, kGap);
  btRigidBody& wheel = hoveringWheel(ours, kGap);
  const auto detect = [&](btScalar falling) {
    for (btRigidBody* body : {&theirs, &wheel}) body->setLinearVelocity(btVector3(0, 0, -falling));
    for (World* world : {&bullets, &ours}) world->world.performDiscreteCollisionDetection();
  };
  detect(0);  // at rest: Bullet keeps the rim's points within 2 cm, which the solver would leave at zero
  EXPECT_GT(wheelPoints(bullets), 0);
  EXPECT_EQ(wheelPoints(ours), 0);
  EXPECT_EQ(ours.dispatcher.getNumManifolds(), 0);  // nor a manifold for them
  detect(0.5);  // falling fast enough to touch within the substep: Bullet's points
  ASSERT_GT(wheelPoints(bullets), 0);
  ASSERT_EQ(wheelPoints(ours), wheelPoints(bullets));
  const btPersistentManifold& expected = *bullets.dispatcher.getManifoldByIndexInternal(0);
  const btPersistentManifold& actual = *ours.dispatcher.getManifoldByIndexInternal(0);
  for (int p = 0; p < expected.getNumContacts(); ++p) {
    EXPECT_EQ(expected.getContactPoint(p).m_positionWorldOnB, actual.getContactPoint(p).m_positionWorldOnB);
    EXPECT_EQ(expected.getContactPoint(p).m_distance1, actual.getContactPoint(p).m_distance1);
  }
  detect(0);  // held again: the points it had go, with their manifold
  EXPECT_EQ(wheelPoints(ours), 0);
  EXPECT_EQ(ours.dispatcher.getNumManifolds(), 0);
  wheel.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.0999)));
  ours.world.performDiscreteCollisionDetection();  // pressed into the ground: touching, whatever its speed
  EXPECT_GT(wheelPoints(ours), 0);
}

}  // namespace
}  // namespace bullet_sim
