// What the pictures of a running simulation keep from step to step: each robot's path as a trail, and the
// schedule of periodic frames. ROS-free: the node feeds it after every step, as any other runner may.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/scene/scene.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

class Recording {
 public:
  /// `frame_period` [s] of sim time between periodic frames; 0 = none.
  explicit Recording(double frame_period) : frame_period_(frame_period), next_frame_(frame_period) {}

  /// Extends the trails; returns the file name of the periodic frame due now ("frame_000001.png"), if any.
  std::optional<std::string> afterStep(const Simulation& simulation);
  /// Every robot's trail: its root link's path, a point every 0.1 s of sim time.
  std::vector<Polyline> trails() const;
  /// Drops the trail of a robot that is gone.
  void forget(const std::string& robot) { trails_.erase(robot); }
  /// After reset_world: the trails start again.
  void clearTrails() { trails_.clear(); }
  /// After reset_simulation: time restarts, and so do the trails and the frame schedule.
  void restart();

 private:
  double frame_period_;
  double next_frame_;
  int frames_ = 0;
  double next_trail_point_ = 0;
  std::map<std::string, Polyline> trails_;
};

}  // namespace bullet_sim
