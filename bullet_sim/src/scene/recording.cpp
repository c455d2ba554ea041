#include "bullet_sim/scene/recording.h"

#include <cstdio>

namespace bullet_sim {

namespace {
constexpr double kTrailSpacing = 0.1;      // [s] of sim time between trail points
constexpr size_t kMaxTrailPoints = 10000;  // 1000 s of trail
constexpr double kTimeEpsilon = 1e-9;      // [s] sim time is a whole number of steps
}  // namespace

std::optional<std::string> Recording::afterStep(const Simulation& simulation) {
  const double now = simulation.time();
  if (now + kTimeEpsilon >= next_trail_point_) {
    next_trail_point_ = now + kTrailSpacing;
    for (const auto& name : simulation.robotNames()) {
      const Robot& robot = *simulation.robot(name);
      auto& points = trails_[name].points;
      if (points.size() < kMaxTrailPoints) {
        points.push_back(robot.body().linkPose(robot.body().spec().root).translation());
      }
    }
  }
  if (frame_period_ <= 0 || now + kTimeEpsilon < next_frame_) return std::nullopt;
  next_frame_ = now + frame_period_;
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06d.png", ++frames_);
  return std::string(name);
}

std::vector<Polyline> Recording::trails() const {
  std::vector<Polyline> trails;
  for (const auto& [name, trail] : trails_) trails.push_back(trail);
  return trails;
}

void Recording::restart() {
  trails_.clear();
  next_trail_point_ = 0;
  next_frame_ = frame_period_;
}

}  // namespace bullet_sim
