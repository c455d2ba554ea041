#include "bullet_shapes.h"

#include <BulletCollision/CollisionShapes/btShapeHull.h>
#include <LinearMath/btAabbUtil2.h>

namespace bullet_sim {

namespace {
constexpr double kHullMargin = 0.001;  // [m] Bullet inflates hulls by their margin; keep it small
}

btCollisionShape* BulletShapes::make(const Shape& shape, bool moving) {
  std::unique_ptr<btCollisionShape> made;
  switch (shape.type) {
    case Shape::Type::kBox:
      made = std::make_unique<btBoxShape>(toBullet(shape.box_size / 2));
      break;
    case Shape::Type::kCylinder:
      made = std::make_unique<btCylinderShapeZ>(btVector3(shape.radius, shape.radius, shape.length / 2));
      break;
    case Shape::Type::kSphere:
      made = std::make_unique<btSphereShape>(shape.radius);
      break;
    case Shape::Type::kPlane:
      if (moving) return nullptr;
      made = std::make_unique<btStaticPlaneShape>(toBullet(shape.plane_normal), 0);
      break;
    case Shape::Type::kMesh: {
      if (!shape.mesh) return nullptr;
      if (moving && shape.convex_parts) {
        return makeParts(*shape.convex_parts);
      } else if (moving) {
        btConvexHullShape full;
        for (const auto& v : shape.mesh->vertices) full.addPoint(toBullet(v), false);
        // btShapeHull samples the shape's support points margin included: Bullet's default 4 cm margin would
        // grow the hull by 4 cm all round (a MiR's caster forks then held its drive wheels 7 mm off the
        // floor).
        full.setMargin(0);
        full.recalcLocalAabb();
        btShapeHull simplified(&full);
        simplified.buildHull(kHullMargin);
        auto hull = std::make_unique<btConvexHullShape>(&simplified.getVertexPointer()->getX(),
                                                        simplified.numVertices(), sizeof(btVector3));
        hull->setMargin(kHullMargin);
        made = std::move(hull);
      } else {
        auto triangles = std::make_unique<btTriangleMesh>();
        for (const auto& t : shape.mesh->triangles) {
          triangles->addTriangle(toBullet(shape.mesh->vertices[t[0]]), toBullet(shape.mesh->vertices[t[1]]),
                                 toBullet(shape.mesh->vertices[t[2]]));
        }
        made = std::make_unique<btBvhTriangleMeshShape>(triangles.get(), true);
        triangle_meshes_.push_back(std::move(triangles));
      }
      break;
    }
  }
  shapes_.push_back(std::move(made));
  return shapes_.back().get();
}

btCompoundShape* BulletShapes::makeParts(const ConvexParts& parts) {
  btCompoundShape* compound = makeCompound();
  for (const auto& points : parts.hulls) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (const Eigen::Vector3d& point : points) hull->addPoint(toBullet(point), false);
    hull->recalcLocalAabb();
    hull->setMargin(kHullMargin);
    compound->addChildShape(btTransform::getIdentity(), hull.get());
    shapes_.push_back(std::move(hull));
  }
  return compound;
}

int BulletShapes::addTo(btCompoundShape& compound, const btTransform& where, const Shape& shape,
                        bool moving) {
  btCollisionShape* made = make(shape, moving);
  if (!made) return 0;
  if (made->getShapeType() != COMPOUND_SHAPE_PROXYTYPE) {
    compound.addChildShape(where, made);
    return 1;
  }
  auto& parts = static_cast<btCompoundShape&>(*made);
  for (int k = 0; k < parts.getNumChildShapes(); ++k)
    compound.addChildShape(where * parts.getChildTransform(k), parts.getChildShape(k));
  return parts.getNumChildShapes();
}

btCompoundShape* BulletShapes::makeCompound() {
  shapes_.push_back(std::make_unique<btCompoundShape>());
  return static_cast<btCompoundShape*>(shapes_.back().get());
}

btCompoundShape* BulletShapes::makeCompound(const btTransform& bounds_frame) {
  shapes_.push_back(std::make_unique<FramedCompound>(bounds_frame));
  return static_cast<btCompoundShape*>(shapes_.back().get());
}

void FramedCompound::recalculateLocalAabb() {
  btCompoundShape::recalculateLocalAabb();
  const btTransform to_frame = frame_.inverse();
  min_.setValue(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT);
  max_ = -min_;
  for (int c = 0; c < getNumChildShapes(); ++c) {
    btVector3 child_min, child_max;
    getChildShape(c)->getAabb(to_frame * getChildTransform(c), child_min, child_max);
    min_.setMin(child_min);
    max_.setMax(child_max);
  }
  bounded_children_ = getNumChildShapes();
}

void FramedCompound::getAabb(const btTransform& pose, btVector3& min, btVector3& max) const {
  if (bounded_children_ != getNumChildShapes() || bounded_children_ == 0) {
    btCompoundShape::getAabb(pose, min, max);
    return;
  }
  btTransformAabb(min_, max_, getMargin(), pose * frame_, min, max);
}

}  // namespace bullet_sim
