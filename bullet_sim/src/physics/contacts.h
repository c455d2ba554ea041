// Contacts per named collision, read from Bullet's contact manifolds after a step (private to the physics
// layer). Every collision object the simulation adds points, through its user pointer, at the Gazebo names of
// its collisions.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/model/gazebo_names.h"
#include "bullet_sim/physics/robot_body.h"

class btCollisionObject;
class btCollisionWorld;
class btManifoldPoint;

namespace bullet_sim {

/// [m/s] beyond its approach, how fast a body may close a gap within one solve (other contacts' impulses).
constexpr double kSpeculativeSlack = 0.2;

/// [m] the widest gap a body approaching at `approach` [m/s] under `gravity` [m/s^2] may close within a
/// substep of `dt` [s]. A wider one's solver row would stay at zero impulse: the contact is out of reach.
inline double reachableGap(double approach, double gravity, double dt) {
  return (approach + gravity * dt + kSpeculativeSlack) * dt;
}

/// Adjusts, before each solve, the contacts of a collision object whose surface moves on its own (a wheel
/// that spins): their friction and the motion their friction aims at. Before each substep, it is shown its
/// contacts with the impulses the last solve gave them.
class ContactTuner {
 public:
  virtual ~ContactTuner() = default;
  /// `point` touches the object's child `child`; `ours_is_a` when the object is the manifold's body A.
  /// `joining`: the other body tuned the point first in this solve (two spinning rims meet), so this one adds
  /// its surface's motion to the other's, along the directions the other chose, and keeps the weaker grip.
  /// Whether it tuned the point.
  virtual bool tune(btManifoldPoint& point, int child, bool ours_is_a, bool joining) const = 0;
  /// `point`, with the impulses of the last solve, touches the object's child `child`.
  virtual void weigh(const btManifoldPoint& point, int child) = 0;
};

/// The Gazebo names (model::link::collision) of a collision object's collisions and their friction
/// coefficients, by compound child index; a simple shape has one. And its ContactTuner, if its contacts need
/// one.
struct CollisionNames {
  std::vector<std::string> names;
  std::vector<double> mu;  ///< as names: each collision's Gazebo mu (a URDF link's <mu1>)
  ContactTuner* tuner = nullptr;
  /// The name of child `index`: the only one for a simple shape (whose index may be a triangle's).
  const std::string& at(int index) const;
  /// The mu of child `index`, found as at() finds its name; 1 (Gazebo's default) for an unknown child.
  double muAt(int index) const;
  /// Appends collision `index` of `from` `count` times: a mesh's convex parts are children of their own.
  void append(const CollisionNames& from, size_t index, int count);
};

/// The names and mu of collisions `sources` of robot `spec`, named `robot`, as Gazebo names them (`gazebo`:
/// gazeboCollisions(spec), which a robot of many parts computes once).
CollisionNames robotCollisionNames(const std::string& robot, const ModelSpec& spec,
                                   const std::vector<GazeboCollision>& gazebo,
                                   const std::vector<CollisionSource>& sources);

/// The friction coefficient of a contact between child `child0` of `object0` and child `child1` of `object1`:
/// the lesser of their mu, as Gazebo's ODE contacts take it (Bullet's default multiplies them).
double contactFriction(const btCollisionObject& object0, int child0, const btCollisionObject& object1,
                       int child1);

/// Makes `object`'s user pointer point at `names`, which must outlive it.
void nameCollisions(btCollisionObject& object, const CollisionNames& names);

/// The ContactTuner of `object` (through its CollisionNames), or nullptr.
ContactTuner* tunerOf(const btCollisionObject& object);

/// What children `first` to `first + count - 1` of `object` (one collision: a mesh may be several convex
/// parts) touch in `world`'s contact manifolds, after a step of `dt` [s]: the points that touch (no gap, or a
/// force), grouped by the other collision.
std::vector<CollisionContact> contactsOf(btCollisionWorld& world, const btCollisionObject& object, int first,
                                         int count, double dt);
/// What child `child` of `object` touches.
inline std::vector<CollisionContact> contactsOf(btCollisionWorld& world, const btCollisionObject& object,
                                                int child, double dt) {
  return contactsOf(world, object, child, 1, dt);
}

}  // namespace bullet_sim
