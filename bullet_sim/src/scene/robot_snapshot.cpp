#include "bullet_sim/scene/robot_snapshot.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "bullet_sim/plugins/pinhole_camera.h"
#include "bullet_sim/plugins/ray_lidar.h"
#include "bullet_sim/scene/scene_builder.h"
#include "bullet_sim/scene/simulation_images.h"

namespace bullet_sim {

namespace {

constexpr double kLidarHitSize = 4;  // [px]
// [m] A plan outlines what stands this much above what lies beside it: a seat, a table top, a wall.
constexpr double kPlanOutlineStep = 0.02;

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
  const WorldSpec& world = simulation.world();
  for (size_t m = 0; m < world.models.size(); ++m) {  // where the world API and the physics put them
    for (size_t v = 0; v < world.models[m].visuals.size(); ++v) {
      scene.meshes.push_back(visualMesh(world.models[m].visuals[v], simulation.worldVisualFrame(m, v)));
    }
  }
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
  if (view == View::kTop) scene.outline_step = kPlanOutlineStep;
  return scene;
}

std::optional<CameraView> parseCameraView(const std::string& name) {
  for (const auto& [prefix, depth] : {std::pair<std::string, bool>{"camera:", false}, {"depth:", true}}) {
    if (name.rfind(prefix, 0) == 0 && name.size() > prefix.size()) return CameraView{name.substr(prefix.size()), depth};
  }
  return std::nullopt;
}

namespace {

/// The robot's camera of that sensor or camera name, and its body; nullptr and the names there are if none.
std::pair<const PinholeCamera*, const RobotBody*> findCamera(const Simulation& simulation, const std::string& name,
                                                             std::string* names) {
  for (const std::string& robot_name : simulation.robotNames()) {
    const Robot& robot = *simulation.robot(robot_name);
    for (const PinholeCamera* camera : robot.pluginsOf<PinholeCamera>()) {
      if (camera->name() == name || camera->config().camera_name == name) return {camera, &robot.body()};
      *names += (names->empty() ? "" : ", ") + camera->name();
    }
  }
  return {nullptr, nullptr};
}

/// Depth as grey, over `image`: white at the near clip, black at `far` and where nothing is seen.
void drawDepth(const std::vector<float>& depths, double near, double far, Image& image) {
  for (size_t p = 0; p < depths.size(); ++p) {
    const double depth = depths[p];
    const double share = std::isfinite(depth) ? std::clamp((far - depth) / (far - near), 0.0, 1.0) : 0.0;
    for (size_t c = 0; c < 3; ++c) image.rgba[p * 4 + c] = static_cast<uint8_t>(std::lround(255 * share));
  }
}

}  // namespace

Image cameraImage(const Simulation& simulation, const CameraView& view, SceneRenderer& renderer) {
  std::string names;
  const auto [camera, body] = findCamera(simulation, view.camera, &names);
  if (!camera) {
    throw std::invalid_argument("no robot has a camera [" + view.camera + "]; the cameras are: [" + names + "]");
  }
  const PinholeCameraConfig& config = camera->config();
  if (view.depth && !config.depth) {
    throw std::invalid_argument("camera [" + view.camera + "] has no depth: it is not a depth sensor");
  }
  // Drawn as the camera's image source draws it, without its noise; the renderer's RGBA is the picture.
  SimulationImages images(simulation, [&renderer]() -> SceneRenderer& { return renderer; });
  const ImageRequest request = camera->imageRequest(*body, view.depth);
  std::vector<float> depths;
  Image image = renderer.render(images.sceneFor(request), request.width, request.height,
                                view.depth ? &depths : nullptr);
  if (view.depth) drawDepth(depths, config.near_clip, std::min(config.far_clip, config.cloud_cutoff_max), image);
  return image;
}

Image snapshotCamera(WorldSpec world, ModelSpec model, const SpawnPose& pose, const CameraView& view,
                     SceneRenderer& renderer, std::vector<std::string>* warnings) {
  Simulation simulation(std::move(world));
  const std::string name = model.name;
  simulation.spawn(name, std::move(model), pose, warnings);
  for (long step = 0; step < std::lround(kSnapshotMaxSimTime / simulation.stepSize()); ++step) simulation.step();
  return cameraImage(simulation, view, renderer);
}

}  // namespace bullet_sim
