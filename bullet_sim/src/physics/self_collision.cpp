#include "physics/self_collision.h"

namespace bullet_sim {

bool SelfCollisionRule::collide(int part_a, int part_b) const {
  if (part_a == part_b || parent_.at(part_a) == part_b || parent_.at(part_b) == part_a) return false;
  return self_collide_.at(part_a) || self_collide_.at(part_b);
}

bool SelfCollisionRule::any() const {
  const int parts = static_cast<int>(self_collide_.size());
  for (int a = 0; a < parts; ++a) {
    for (int b = a + 1; b < parts; ++b) {
      if (collide(a, b)) return true;
    }
  }
  return false;
}

bool RuledLinkCollider::checkCollideWithOverride(const btCollisionObject* other) const {
  const btMultiBodyLinkCollider* link = btMultiBodyLinkCollider::upcast(other);
  if (!link || link->m_multiBody != m_multiBody) return true;
  return rule_.collide(m_link + 1, link->m_link + 1);
}

}  // namespace bullet_sim
