#include "bullet_sim/scene/robot_snapshot.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "bullet_sim/plugins/ray_lidar.h"
#include "bullet_sim/scene/scene_builder.h"

namespace bullet_sim {

namespace {

constexpr double kLidarHitSize = 4;  // [px]

std::string noScanWarning(const RayLidar& lidar) {
  std::ostringstream warning;
  warning << "lidar [" << lidar.name() << "] on link [" << lidar.config().link << "] produced no scan within "
          << kSnapshotMaxSimTime << " s of sim time (its update_rate is " << lidar.config().update_rate
          << " Hz), so its hits are not drawn";
  return warning.str();
}

}  // namespace

RobotSnapshot snapshotRobot(WorldSpec world, ModelSpec model, const SpawnPose& pose, View view) {
  RobotSnapshot snapshot;
  Simulation simulation(std::move(world));
  const std::string name = model.name;
  Robot& robot = simulation.spawn(name, std::move(model), pose, &snapshot.warnings);

  const std::vector<RayLidar*> lidars = robot.pluginsOf<RayLidar>();
  const auto max_steps = std::lround(kSnapshotMaxSimTime / simulation.stepSize());
  const auto all_scanned = [&] {
    return std::all_of(lidars.begin(), lidars.end(),
                       [](const RayLidar* lidar) { return lidar->scanCount() > 0; });
  };
  for (long step = 0; step < max_steps && !all_scanned(); ++step) simulation.step();

  for (const RayLidar* lidar : lidars) {
    if (lidar->scanCount() == 0) snapshot.warnings.push_back(noScanWarning(*lidar));
  }
  snapshot.scene = simulationScene(simulation, view, name);
  return snapshot;
}

Scene simulationScene(const Simulation& simulation, View view, const std::string& focus,
                      const std::vector<Polyline>& trails) {
  Scene scene;
  addWorld(scene, simulation.world());
  const std::vector<std::string> names = simulation.robotNames();
  Eigen::Isometry3d focus_pose = Eigen::Isometry3d::Identity();
  Eigen::AlignedBox3d focus_bounds;
  for (const auto& name : names) {
    const Robot& robot = *simulation.robot(name);
    const ModelSpec& spec = robot.body().spec();
    std::map<std::string, Eigen::Isometry3d> link_poses;
    for (const LinkSpec& link : spec.links) link_poses[link.name] = robot.body().linkPose(link.name);
    const Eigen::AlignedBox3d bounds = addModel(scene, spec, link_poses);
    if (name == focus || (name == names.front() && focus_bounds.isEmpty())) {
      focus_pose = robot.body().linkPose(spec.root);
      focus_bounds = bounds;
    }
    for (const RayLidar* lidar : robot.pluginsOf<RayLidar>()) {
      if (lidar->scanCount() == 0) continue;
      // Red: no shipped robot or world uses it.
      PointSet hits = lidar->config().output == RayLidarConfig::Output::kLaserScan
                          ? lidarHits(lidar->scan(), Eigen::Vector4d(1, 0, 0, 1), kLidarHitSize)
                          : cloudHits(lidar->cloud(), Eigen::Vector4d(1, 0, 0, 1), kLidarHitSize);
      // A plan looks down on table tops and wall tops, which would hide the hits beneath them.
      hits.overlay = view == View::kTop;
      scene.point_sets.push_back(std::move(hits));
    }
  }
  scene.polylines = trails;
  scene.camera = viewCamera(view, focus_pose, focus_bounds, worldBounds(simulation.world()));
  return scene;
}

}  // namespace bullet_sim
