#include "physics/contacts.h"

#include <btBulletCollisionCommon.h>

#include <algorithm>

#include "bullet_shapes.h"

namespace bullet_sim {

namespace {

const std::string kUnnamed;
constexpr double kGazeboMu = 1.0;  // a surface's mu where none is given

const std::string& nameOf(const btCollisionObject* object, int child) {
  const auto* names = static_cast<const CollisionNames*>(object->getUserPointer());
  return names ? names->at(child) : kUnnamed;
}

/// The point as felt by the side `ours` (0 for body A, 1 for body B).
ContactPoint pointOn(const btManifoldPoint& point, int ours, double dt) {
  const double sign = ours == 0 ? 1.0 : -1.0;  // the normal points from B to A
  ContactPoint contact;
  contact.position = fromBullet(ours == 0 ? point.getPositionWorldOnA() : point.getPositionWorldOnB());
  contact.normal = sign * fromBullet(point.m_normalWorldOnB);
  contact.depth = std::max(0.0, -static_cast<double>(point.getDistance()));
  const btVector3 impulse = point.m_normalWorldOnB * point.m_appliedImpulse +
                            point.m_lateralFrictionDir1 * point.m_appliedImpulseLateral1 +
                            point.m_lateralFrictionDir2 * point.m_appliedImpulseLateral2;
  contact.force = sign * fromBullet(impulse) / dt;
  return contact;
}

}  // namespace

const std::string& CollisionNames::at(int index) const {
  if (names.size() == 1) return names.front();
  return index >= 0 && index < static_cast<int>(names.size()) ? names[index] : kUnnamed;
}

double CollisionNames::muAt(int index) const {
  if (mu.size() == 1) return mu.front();
  return index >= 0 && index < static_cast<int>(mu.size()) ? mu[index] : kGazeboMu;
}

void CollisionNames::append(const CollisionNames& from, size_t index, int count) {
  names.insert(names.end(), count, from.names.at(index));
  mu.insert(mu.end(), count, from.mu.at(index));
}

CollisionNames robotCollisionNames(const std::string& robot, const ModelSpec& spec,
                                   const std::vector<GazeboCollision>& gazebo,
                                   const std::vector<CollisionSource>& sources) {
  CollisionNames named;
  for (const CollisionSource& source : sources) {
    const auto found = std::find_if(gazebo.begin(), gazebo.end(), [&](const GazeboCollision& collision) {
      return collision.link == source.link && collision.index == source.index;
    });
    const bool known = found != gazebo.end();
    named.names.push_back(known ? robot + "::" + found->gazebo_link + "::" + found->name : "");
    const LinkSpec* link = spec.link(source.link);
    named.mu.push_back(link ? link->surface.mu1 : kGazeboMu);
  }
  return named;
}

double contactFriction(const btCollisionObject& object0, int child0, const btCollisionObject& object1,
                       int child1) {
  const auto* names0 = static_cast<const CollisionNames*>(object0.getUserPointer());
  const auto* names1 = static_cast<const CollisionNames*>(object1.getUserPointer());
  return std::min(names0 ? names0->muAt(child0) : object0.getFriction(),
                  names1 ? names1->muAt(child1) : object1.getFriction());
}

void nameCollisions(btCollisionObject& object, const CollisionNames& names) {
  object.setUserPointer(const_cast<CollisionNames*>(&names));  // Bullet's user pointer is not const
}

ContactTuner* tunerOf(const btCollisionObject& object) {
  const auto* names = static_cast<const CollisionNames*>(object.getUserPointer());
  return names ? names->tuner : nullptr;
}

std::vector<CollisionContact> contactsOf(btCollisionWorld& world, const btCollisionObject& object, int first,
                                         int count, double dt) {
  std::vector<CollisionContact> contacts;
  btDispatcher& dispatcher = *world.getDispatcher();  // its manifold getters are not const
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
    const int ours = manifold.getBody0() == &object ? 0 : manifold.getBody1() == &object ? 1 : -1;
    if (ours < 0) continue;
    const btCollisionObject* other = ours == 0 ? manifold.getBody1() : manifold.getBody0();
    for (int p = 0; p < manifold.getNumContacts(); ++p) {
      const btManifoldPoint& point = manifold.getContactPoint(p);
      const int child = ours == 0 ? point.m_index0 : point.m_index1;
      if (child < first || child >= first + count) continue;
      if (point.getDistance() > 0 && point.m_appliedImpulse <= 0) continue;  // near, not touching
      const std::string& other_name = nameOf(other, ours == 0 ? point.m_index1 : point.m_index0);
      auto found = std::find_if(contacts.begin(), contacts.end(),
                                [&](const CollisionContact& contact) { return contact.other == other_name; });
      if (found == contacts.end()) found = contacts.insert(contacts.end(), {other_name, {}});
      found->points.push_back(pointOn(point, ours, dt));
    }
  }
  return contacts;
}

}  // namespace bullet_sim
