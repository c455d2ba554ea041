#include "bench/fleet_watch.h"

#include <algorithm>

#include "bullet_sim/model/model_geometry.h"

namespace bullet_sim {
namespace {

Eigen::Isometry3d rootPose(const Robot& robot) { return robot.body().linkPose(robot.body().spec().root); }

/// The part whose frame is the robot's root link's, or -1.
int rootPart(const Robot& robot) {
  const RobotBody& body = robot.body();
  const int part = body.partOf(body.spec().root);
  return part >= 0 && body.parts()[part].root_link == body.spec().root ? part : -1;
}

}  // namespace

FleetWatch::FleetWatch(Simulation& simulation, std::vector<const Robot*> robots)
    : simulation_(simulation), robots_(std::move(robots)) {
  const WorldSpec& world = simulation.world();
  for (size_t model = 0; model < world.models.size(); ++model) {
    const WorldModelSpec& spec = world.models[model];
    if (!spec.is_static) {
      loose_models_.push_back(model);
      LooseBodyTrack track;
      track.name = spec.name;
      track.start = simulation.worldModelPose(model).translation();
      loose_.push_back(track);
      continue;
    }
    for (const Collision& collision : spec.collisions) {
      const Eigen::Isometry3d pose = spec.pose * collision.origin;
      const bool horizontal_plane = collision.shape.type == Shape::Type::kPlane &&
                                    (pose.linear() * collision.shape.plane_normal).z() > 1 - 1e-9;
      if (horizontal_plane) ground_ = std::max(ground_, pose.translation().z());
      const Eigen::AlignedBox3d bounds = boundingBox(collision.shape, pose);
      if (bounds.isEmpty()) continue;
      static_boxes_.push_back(bounds);
      static_bounds_.extend(bounds);
    }
  }
  for (const Robot* robot : robots_) {
    root_parts_.push_back(rootPart(*robot));
    RobotTrack track;
    const Eigen::Vector3d root = rootPose(*robot).translation();
    track.z_start = root.z();
    robot_tracks_.push_back(track);
    for (const LooseBodyTrack& body : loose_)
      start_clearance_ = std::min(start_clearance_, (body.start - root).head<2>().norm());
  }
  sample();
}

void FleetWatch::sample() {
  for (size_t k = 0; k < loose_models_.size(); ++k) {
    LooseBodyTrack& track = loose_[k];
    const Robot* body = simulation_.worldBody(loose_models_[k]);
    const bool asleep = body && body->body().sleeping();
    if (asleep && track.asleep) continue;  // it has not moved since the last sample
    track.asleep = asleep;
    const Eigen::Vector3d centre = simulation_.worldModelPose(loose_models_[k]).translation();
    track.end = centre;
    track.z_min = std::min(track.z_min, centre.z());
    track.z_max = std::max(track.z_max, centre.z());
    track.moved_max = std::max(track.moved_max, (centre - track.start).head<2>().norm());
    const Eigen::Vector2d low = static_bounds_.min().head<2>(), high = static_bounds_.max().head<2>();
    const bool outside = !static_bounds_.isEmpty() && ((centre.head<2>().array() < low.array()).any() ||
                                                       (centre.head<2>().array() > high.array()).any());
    const auto holds = [&](const Eigen::AlignedBox3d& box) { return box.contains(centre); };
    const bool inside_static = std::any_of(static_boxes_.begin(), static_boxes_.end(), holds);
    if (outside || inside_static || centre.z() < ground_) track.escaped = true;
  }
  for (size_t k = 0; k < robots_.size(); ++k) {
    RobotTrack& track = robot_tracks_[k];
    const RobotBody& body = robots_[k]->body();
    const Eigen::Isometry3d root =
        root_parts_[k] >= 0 ? body.partPose(root_parts_[k]) : rootPose(*robots_[k]);
    track.rise_max = std::max(track.rise_max, root.translation().z() - track.z_start);
    track.sink_max = std::max(track.sink_max, track.z_start - root.translation().z());
    track.up_min = std::min(track.up_min, root.linear()(2, 2));
  }
}

}  // namespace bullet_sim
