// A compound's world bounds, taken about a frame of its owner's choice, hold every child at every pose, and
// hug a chassis whose own axes (its principal axes of inertia) lean away from it.
#include <gtest/gtest.h>

#include <btBulletCollisionCommon.h>

#include <random>

#include "src/physics/bullet_shapes.h"

namespace bullet_sim {
namespace {

const btVector3 kHalfBox(0.6, 0.35, 0.25);  ///< [m] a chassis 1.2 m long, 0.7 m wide, 0.5 m high

/// The chassis's frame in the compound's: turned 35 degrees about x, then 40 about z, as principal axes may
/// be.
btTransform leaningChassis() {
  btQuaternion turn;
  turn.setEulerZYX(0.7, 0.0, 0.6);
  return btTransform(turn, btVector3(0.1, -0.05, 0.2));
}

bool contains(const btVector3& outer_min, const btVector3& outer_max, const btVector3& inner_min,
              const btVector3& inner_max) {
  for (int i = 0; i < 3; ++i) {
    if (inner_min[i] < outer_min[i] - 1e-12 || inner_max[i] > outer_max[i] + 1e-12) return false;
  }
  return true;
}

TEST(FramedCompound, BoundsAChassisAsTightlyAsItsOwnBoxWhenLevel) {
  btBoxShape box(kHalfBox);
  btCompoundShape bullets;
  FramedCompound framed(leaningChassis());
  for (btCompoundShape* compound : {&bullets, static_cast<btCompoundShape*>(&framed)})
    compound->addChildShape(leaningChassis(), &box);
  framed.recalculateLocalAabb();
  // The chassis level and square to the world: its bounds are the box, as the box's own are.
  const btTransform level = leaningChassis().inverse();
  btVector3 min, max, box_min, box_max, bullet_min, bullet_max;
  framed.getAabb(level, min, max);
  box.getAabb(btTransform::getIdentity(), box_min, box_max);
  bullets.getAabb(level, bullet_min, bullet_max);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(min[i], box_min[i], 1e-12) << i;
    EXPECT_NEAR(max[i], box_max[i], 1e-12) << i;
  }
  // Bullet's bounds about the compound's own leaning axes are half as wide again.
  EXPECT_GT(bullet_max.x() - bullet_min.x(), 1.3 * (max.x() - min.x()));
  EXPECT_GT(bullet_max.y() - bullet_min.y(), 1.3 * (max.y() - min.y()));
}

TEST(FramedCompound, HoldsEveryChildAtEveryPoseAndAfterAChildMoves) {
  btBoxShape box(kHalfBox);
  btCylinderShapeZ wheel(btVector3(0.3, 0.3, 0.025));
  FramedCompound framed(leaningChassis());
  framed.addChildShape(leaningChassis(), &box);
  const btTransform hub(btQuaternion(btVector3(1, 0, 0), SIMD_HALF_PI), btVector3(0.5, 0.4, -0.2));
  framed.addChildShape(hub, &wheel);
  framed.recalculateLocalAabb();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> angle(-SIMD_PI, SIMD_PI), offset(-5, 5);
  for (int trial = 0; trial < 200; ++trial) {
    if (trial == 100)  // a steered wheel: its child moves, and the bounds are taken again
      framed.updateChildTransform(1, btTransform(btQuaternion(btVector3(0, 0, 1), 0.8) * hub.getRotation(),
                                                 btVector3(0.9, -0.7, 0.3)));
    btQuaternion turn;
    turn.setEulerZYX(angle(random), angle(random) / 2, angle(random));
    const btTransform pose(turn, btVector3(offset(random), offset(random), offset(random)));
    btVector3 min, max;
    framed.getAabb(pose, min, max);
    for (int c = 0; c < framed.getNumChildShapes(); ++c) {
      btVector3 child_min, child_max;
      framed.getChildShape(c)->getAabb(pose * framed.getChildTransform(c), child_min, child_max);
      EXPECT_TRUE(contains(min, max, child_min, child_max)) << "trial " << trial << ", child " << c;
    }
  }
}

TEST(FramedCompound, GivenAChildSinceItsBoundsWereTakenKeepsBulletsBounds) {
  btBoxShape box(kHalfBox);
  btSphereShape far_sphere(0.2);
  FramedCompound framed(leaningChassis());
  framed.addChildShape(leaningChassis(), &box);
  framed.recalculateLocalAabb();
  framed.addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(3, 0, 0)), &far_sphere);
  btVector3 min, max, sphere_min, sphere_max;
  framed.getAabb(btTransform::getIdentity(), min, max);
  far_sphere.getAabb(framed.getChildTransform(1), sphere_min, sphere_max);
  EXPECT_TRUE(contains(min, max, sphere_min, sphere_max));
}

}  // namespace
}  // namespace bullet_sim
