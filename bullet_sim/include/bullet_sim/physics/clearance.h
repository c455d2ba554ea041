// How near a robot is to a world's obstacles: the distance between its collision shapes and theirs, from
// Bullet's closest-point queries (GJK on convex shapes, triangles of static meshes). Ground truth, unlike a
// lidar, which sees only what its rays cross.
#pragma once

#include <memory>
#include <string>

#include "bullet_sim/model/world.h"
#include "bullet_sim/physics/robot_body.h"

namespace bullet_sim {

struct Clearance {
  double distance = 0;   ///< [m] between the nearest robot collision and obstacle; 0 when they touch
  std::string obstacle;  ///< the world model it is to; "" when nothing is within the query's cap
};

class ClearanceQuery {
 public:
  /// The world's obstacles: every collision of its models but infinite planes (the ground).
  explicit ClearanceQuery(const WorldSpec& world);
  ~ClearanceQuery();
  ClearanceQuery(const ClearanceQuery&) = delete;
  ClearanceQuery& operator=(const ClearanceQuery&) = delete;

  /// The nearest obstacle to `robot`'s collisions where its parts are now, when nearer than `cap` [m];
  /// otherwise {cap, ""}. The robot's shapes are made at its first query and kept: `robot` must outlive them.
  Clearance nearest(const RobotBody& robot, double cap);

 private:
  struct Engine;
  std::unique_ptr<Engine> engine_;
};

}  // namespace bullet_sim
