#include "bullet_sim/scene/robot_snapshot.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "bullet_sim/common/names.h"
#include "bullet_sim/scene/scene_builder.h"
#include "bullet_sim/scene/simulation_images.h"

namespace bullet_sim {

namespace {

constexpr double kLidarHitSize = 4;  // [px]
// [m] A plan outlines what stands this much above what lies beside it: a seat, a table top, a wall.
constexpr double kPlanOutlineStep = 0.02;

/// The sample counts of every output of a robot that holds hits to draw: scans and point clouds.
struct ScanCounts {
  std::vector<RobotOutput<LaserScan>> scans;
  std::vector<RobotOutput<PointCloud>> clouds;
  std::vector<RobotOutput<LegacyPointCloud>> legacy_clouds;

  explicit ScanCounts(const Robot& robot)
      : scans(robot.outputs<LaserScan>()),
        clouds(robot.outputs<PointCloud>()),
        legacy_clouds(robot.outputs<LegacyPointCloud>()) {}

  /// Calls `visit(plugin, count)` for each output.
  template <class Visit>
  void forEach(Visit visit) const {
    for (const auto& output : scans) visit(*output.plugin, output.stream->count());
    for (const auto& output : clouds) visit(*output.plugin, output.stream->count());
    for (const auto& output : legacy_clouds) visit(*output.plugin, output.stream->count());
  }
};

std::string noScanWarning(const Plugin& sensor) {
  std::ostringstream warning;
  warning << sensor.where() << " produced no scan within " << kSnapshotMaxSimTime
          << " s of sim time (its update_rate is " << sensor.updateRate() << " Hz),"
          << " so its hits are not drawn";
  return warning.str();
}

/// Every scan and point cloud a robot published last, as hits; red: no shipped robot or world uses it.
std::vector<PointSet> robotHits(const Robot& robot, View view) {
  const Eigen::Vector4d red(1, 0, 0, 1);
  std::vector<PointSet> hits;
  for (const auto& output : robot.outputs<LaserScan>()) {
    if (output.stream->count() > 0) hits.push_back(lidarHits(output.stream->latest(), red, kLidarHitSize));
  }
  for (const auto& output : robot.outputs<PointCloud>()) {
    if (output.stream->count() > 0) hits.push_back(cloudHits(output.stream->latest(), red, kLidarHitSize));
  }
  for (const auto& output : robot.outputs<LegacyPointCloud>()) {
    if (output.stream->count() > 0) hits.push_back(cloudHits(output.stream->latest(), red, kLidarHitSize));
  }
  // A plan looks down on table tops and wall tops, which would hide the hits beneath them.
  for (PointSet& set : hits) set.overlay = view == View::kTop;
  return hits;
}

}  // namespace

RobotSnapshot snapshotRobot(WorldSpec world, ModelSpec model, const SpawnPose& pose, View view) {
  RobotSnapshot snapshot;
  Simulation simulation(std::move(world));
  const std::string name = model.name;
  Robot& robot = simulation.spawn(name, std::move(model), pose, &snapshot.warnings);

  const ScanCounts scans(robot);
  const auto max_steps = std::lround(kSnapshotMaxSimTime / simulation.stepSize());
  const auto all_scanned = [&] {
    bool all = true;
    scans.forEach([&](const Plugin&, uint64_t count) { all = all && count > 0; });
    return all;
  };
  for (long step = 0; step < max_steps && !all_scanned(); ++step) simulation.step();
  scans.forEach([&](const Plugin& sensor, uint64_t count) {
    if (count == 0) snapshot.warnings.push_back(noScanWarning(sensor));
  });
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
    for (PointSet& hits : robotHits(robot, view)) scene.point_sets.push_back(std::move(hits));
  }
  scene.polylines = trails;
  scene.camera = viewCamera(view, focus_pose, focus_bounds, worldBounds(simulation.world()));
  if (view == View::kTop) scene.outline_step = kPlanOutlineStep;
  return scene;
}

std::optional<CameraView> parseCameraView(const std::string& name) {
  for (const auto& [prefix, depth] : {std::pair<std::string, bool>{"camera:", false}, {"depth:", true}}) {
    if (name.rfind(prefix, 0) == 0 && name.size() > prefix.size())
      return CameraView{name.substr(prefix.size()), depth};
  }
  return std::nullopt;
}

namespace {

/// The robot's camera of that sensor or camera name, and its body; nullptr and the names there are if none.
std::pair<const CameraSensor*, const RobotBody*> findCamera(const Simulation& simulation,
                                                            const std::string& name,
                                                            std::vector<std::string>* names) {
  for (const std::string& robot_name : simulation.robotNames()) {
    const Robot& robot = *simulation.robot(robot_name);
    for (const auto& [plugin, camera] : robot.sensors<CameraSensor>()) {
      if (plugin->name() == name || camera->cameraName() == name) return {camera, &robot.body()};
      names->push_back(plugin->name());
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
  std::vector<std::string> names;
  const auto [camera, body] = findCamera(simulation, view.camera, &names);
  if (!camera) {
    throw std::invalid_argument("no robot has a camera [" + view.camera + "]; the cameras are: [" +
                                joinedNames(names) + "]");
  }
  if (view.depth && !camera->measuresDepth()) {
    throw std::invalid_argument("camera [" + view.camera + "] has no depth: it is not a depth sensor");
  }
  // Drawn as the camera's image source draws it, without its noise; the renderer's RGBA is the picture.
  SimulationImages images(simulation, [&renderer]() -> SceneRenderer& { return renderer; });
  const ImageRequest request = camera->imageRequest(*body, view.depth);
  std::vector<float> depths;
  Image image = renderer.render(images.sceneFor(request), request.width, request.height,
                                view.depth ? &depths : nullptr);
  if (view.depth) drawDepth(depths, camera->depthSpan().first, camera->depthSpan().second, image);
  return image;
}

Image snapshotCamera(WorldSpec world, ModelSpec model, const SpawnPose& pose, const CameraView& view,
                     SceneRenderer& renderer, std::vector<std::string>* warnings) {
  Simulation simulation(std::move(world));
  const std::string name = model.name;
  simulation.spawn(name, std::move(model), pose, warnings);
  for (long step = 0; step < std::lround(kSnapshotMaxSimTime / simulation.stepSize()); ++step)
    simulation.step();
  return cameraImage(simulation, view, renderer);
}

}  // namespace bullet_sim
