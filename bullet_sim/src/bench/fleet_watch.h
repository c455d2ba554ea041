// What a fleet's drive does to the world's loose bodies and to its robots, sampled after every step: the
// check that nothing flew, sank or went through a wall (issue 32's 20 wheelchairs among 200 boxes in a
// walled world).
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

/// One non-static world model (a loose box), by its model frame's origin: its centre for a box posed there.
struct LooseBodyTrack {
  std::string name;                                 ///< the world model's
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  ///< [m] where it was when the watch began
  Eigen::Vector3d end = Eigen::Vector3d::Zero();    ///< [m] at the last sample
  double z_min = INFINITY, z_max = -INFINITY;       ///< [m] its lowest and highest
  double moved_max = 0;  ///< [m] the farthest it went from its start, horizontally
  /// It was once outside the walls (the x-y bounds of the world's static bodies, the ground plane left out),
  /// inside a static body's box bounds, or below the ground plane.
  bool escaped = false;
  bool asleep = false;  ///< Bullet had put it to sleep at the last sample
};

/// One robot, by its root link.
struct RobotTrack {
  double z_start = 0;   ///< [m] when the watch began
  double rise_max = 0;  ///< [m] the most its root link rose above z_start
  double sink_max = 0;  ///< [m] the most it sank below z_start (a robot through the floor)
  double up_min = 1;    ///< the least world z of its root link's z axis
  /// [rad] the most its root link's z axis leaned from the vertical
  double tiltMax() const { return std::acos(std::clamp(up_min, -1.0, 1.0)); }
};

/// Tracks a simulation's loose world bodies and the given robots from its construction on.
class FleetWatch {
 public:
  FleetWatch(Simulation& simulation, std::vector<const Robot*> robots);
  /// Call after each step.
  void sample();
  const std::vector<LooseBodyTrack>& loose() const { return loose_; }
  const std::vector<RobotTrack>& robots() const { return robot_tracks_; }
  /// [m] the smallest horizontal distance from a robot's root link to a loose body when the watch began
  /// (infinite without loose bodies): every robot started free of the boxes when it exceeds their reach.
  double startClearance() const { return start_clearance_; }

 private:
  Simulation& simulation_;
  std::vector<const Robot*> robots_;
  /// Per robot, the part whose frame is its root link's (read every step without looking the link up), or -1.
  std::vector<int> root_parts_;
  std::vector<size_t> loose_models_;  ///< indices into the world's models
  std::vector<LooseBodyTrack> loose_;
  std::vector<RobotTrack> robot_tracks_;
  std::vector<Eigen::AlignedBox3d> static_boxes_;  ///< every static non-plane collision's world bounds
  Eigen::AlignedBox3d static_bounds_;              ///< their union; empty when there are none
  double ground_ = -INFINITY;                      ///< [m] the highest horizontal ground plane's z
  double start_clearance_ = INFINITY;
};

}  // namespace bullet_sim
