// Which parts of one robot collide with each other, as Gazebo decides (private to the physics layer).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <vector>

namespace bullet_sim {

/// SDF's rule, as Gazebo classic applies it: two parts collide when either has <self_collide> (a URDF's
/// <selfCollide>; a part has it when one of its links does), and never when a joint joins them.
class SelfCollisionRule {
 public:
  /// Per part: whether it self-collides, and its parent part (-1 for part 0).
  SelfCollisionRule(std::vector<bool> self_collide, std::vector<int> parent)
      : self_collide_(std::move(self_collide)), parent_(std::move(parent)) {}
  bool collide(int part_a, int part_b) const;
  /// Whether any two parts collide.
  bool any() const;

 private:
  std::vector<bool> self_collide_;
  std::vector<int> parent_;
};

/// A multibody link's collider that asks `rule` whether it meets another part of its multibody, where Bullet
/// would let one flag decide for all of them.
class RuledLinkCollider : public btMultiBodyLinkCollider {
 public:
  /// `link` is Bullet's: -1 for the base (part 0), k - 1 for part k. `rule` must outlive the collider.
  RuledLinkCollider(btMultiBody* body, int link, const SelfCollisionRule& rule)
      : btMultiBodyLinkCollider(body, link), rule_(rule) {}
  bool checkCollideWithOverride(const btCollisionObject* other) const override;

 private:
  const SelfCollisionRule& rule_;
};

}  // namespace bullet_sim
