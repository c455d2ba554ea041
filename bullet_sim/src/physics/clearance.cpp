#include "bullet_sim/physics/clearance.h"

#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <map>
#include <vector>

#include "bullet_shapes.h"

namespace bullet_sim {

namespace {

/// The smallest distance of the points Bullet reports for a pair (negative when they overlap).
struct NearestPoint : btCollisionWorld::ContactResultCallback {
  double distance;
  explicit NearestPoint(double cap) : distance(cap) {
    m_closestDistanceThreshold = static_cast<btScalar>(cap);
  }
  btScalar addSingleResult(btManifoldPoint& point, const btCollisionObjectWrapper*, int, int,
                           const btCollisionObjectWrapper*, int, int) override {
    distance = std::min(distance, static_cast<double>(point.getDistance()));
    return 0;
  }
};

struct Obstacle {
  std::string name;
  std::unique_ptr<btCollisionObject> object;
  btVector3 aabb_min, aabb_max;
};

}  // namespace

struct ClearanceQuery::Engine {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};
  BulletShapes shapes;
  std::vector<Obstacle> obstacles;
  /// Per robot body, per part: an object holding the part's collisions (null for a part without any).
  std::map<const RobotBody*, std::vector<std::unique_ptr<btCollisionObject>>> robots;

  std::vector<std::unique_ptr<btCollisionObject>>& robotObjects(const RobotBody& robot) {
    auto& objects = robots[&robot];
    if (!objects.empty() || robot.parts().empty()) return objects;
    for (const RobotPart& part : robot.parts()) {
      btCompoundShape* compound = shapes.makeCompound();
      for (const Collision& collision : part.collisions) {
        if (btCollisionShape* shape = shapes.make(collision.shape, /*moving=*/true))
          compound->addChildShape(toBullet(collision.origin), shape);
      }
      objects.push_back(nullptr);
      if (compound->getNumChildShapes() == 0) continue;
      objects.back() = std::make_unique<btCollisionObject>();
      objects.back()->setCollisionShape(compound);
    }
    return objects;
  }
};

ClearanceQuery::ClearanceQuery(const WorldSpec& world) : engine_(std::make_unique<Engine>()) {
  for (const WorldModelSpec& model : world.models) {
    btCompoundShape* compound = engine_->shapes.makeCompound();
    for (const Collision& collision : model.collisions) {
      if (collision.shape.type == Shape::Type::kPlane) continue;
      if (btCollisionShape* shape = engine_->shapes.make(collision.shape, /*moving=*/false))
        compound->addChildShape(toBullet(collision.origin), shape);
    }
    if (compound->getNumChildShapes() == 0) continue;
    Obstacle obstacle{model.name, std::make_unique<btCollisionObject>(), {}, {}};
    obstacle.object->setCollisionShape(compound);
    obstacle.object->setWorldTransform(toBullet(model.pose));
    compound->getAabb(obstacle.object->getWorldTransform(), obstacle.aabb_min, obstacle.aabb_max);
    engine_->obstacles.push_back(std::move(obstacle));
  }
}

ClearanceQuery::~ClearanceQuery() = default;

Clearance ClearanceQuery::nearest(const RobotBody& robot, double cap) {
  Clearance nearest{cap, ""};
  auto& parts = engine_->robotObjects(robot);
  const btVector3 margin(cap, cap, cap);
  for (size_t k = 0; k < parts.size(); ++k) {
    if (!parts[k]) continue;
    btCollisionObject& part = *parts[k];
    part.setWorldTransform(toBullet(robot.partPose(static_cast<int>(k))));
    btVector3 low, high;
    part.getCollisionShape()->getAabb(part.getWorldTransform(), low, high);
    low -= margin;
    high += margin;
    for (Obstacle& obstacle : engine_->obstacles) {
      if (!TestAabbAgainstAabb2(low, high, obstacle.aabb_min, obstacle.aabb_max)) continue;
      NearestPoint result(nearest.distance);
      engine_->world.contactPairTest(&part, obstacle.object.get(), result);
      if (result.distance < nearest.distance) nearest = {std::max(0.0, result.distance), obstacle.name};
    }
  }
  return nearest;
}

}  // namespace bullet_sim
