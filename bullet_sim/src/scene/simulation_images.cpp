#include "bullet_sim/scene/simulation_images.h"

#include <cmath>
#include <utility>

#include "bullet_sim/scene/scene_builder.h"

namespace bullet_sim {

namespace {

const Eigen::Vector4d kGazeboBackground{0.7, 0.7, 0.7, 1};  // SDF's default <scene><background>

/// The view camera of an image request: at its pose looking along its x axis, its field of view and clips.
Camera requestCamera(const ImageRequest& request) {
  const double aspect = static_cast<double>(request.width) / request.height;
  const double vertical_fov = 2 * std::atan(std::tan(request.horizontal_fov / 2) / aspect);
  Camera camera = cameraAt(request.pose, vertical_fov);
  camera.near_clip = request.near_clip;
  camera.far_clip = request.far_clip;
  return camera;
}

}  // namespace

SimulationImages::SimulationImages(const Simulation& simulation, RendererAccess renderer)
    : simulation_(simulation), renderer_(std::move(renderer)) {
  const WorldSpec& world = simulation_.world();
  for (size_t m = 0; m < world.models.size(); ++m) {
    for (size_t v = 0; v < world.models[m].visuals.size(); ++v) {
      const Visual& visual = world.models[m].visuals[v];
      world_visuals_.push_back({m, v, visual.origin});
      scene_.meshes.push_back(visualMesh(visual, Eigen::Isometry3d::Identity()));
    }
  }
  scene_.ground_grid = false;
  scene_.background = kGazeboBackground;
}

void SimulationImages::refreshRobots() {
  const std::vector<std::string> names = simulation_.robotNames();
  for (auto it = robots_.begin(); it != robots_.end();) {
    const Robot* robot = simulation_.robot(it->first);
    it = robot && &robot->body() == it->second.body ? std::next(it) : robots_.erase(it);
  }
  for (const std::string& name : names) {
    if (robots_.count(name)) continue;
    const PhysicsRobot& body = simulation_.robot(name)->body();
    RobotVisuals& entry = robots_[name];
    entry.body = &body;
    for (const LinkSpec& link : body.spec().links) {
      if (link.visuals.empty()) continue;
      LinkVisuals& visuals = entry.links.emplace_back();
      visuals.link = link.name;
      for (const Visual& visual : link.visuals) {
        visuals.meshes.push_back(visualMesh(visual, Eigen::Isometry3d::Identity()));
      }
    }
  }
}

const Scene& SimulationImages::sceneFor(const ImageRequest& request) {
  refreshRobots();
  scene_.meshes.resize(world_visuals_.size());
  for (size_t k = 0; k < world_visuals_.size(); ++k) {  // the world API may have moved world models
    const WorldVisual& visual = world_visuals_[k];
    scene_.meshes[k].pose = simulation_.worldVisualFrame(visual.model, visual.index) * visual.origin;
  }
  for (const auto& [name, robot] : robots_) {
    for (const LinkVisuals& link : robot.links) {
      const Eigen::Isometry3d link_pose = robot.body->linkPose(link.link);
      for (const SceneMesh& visual : link.meshes) {
        scene_.meshes.push_back(visual);
        scene_.meshes.back().pose = link_pose * visual.pose;
      }
    }
  }
  scene_.camera = requestCamera(request);
  return scene_;
}

void SimulationImages::render(const ImageRequest& request, RenderedImage& image) {
  const Scene& scene = sceneFor(request);
  if (!request.depth) image.depth.clear();
  renderer_().renderRgb(scene, request.width, request.height, image.rgb,
                        request.depth ? &image.depth : nullptr);
  image.width = request.width;
  image.height = request.height;
}

ImageSourceFactory imagesFrom(RendererAccess renderer) {
  return [renderer](const Simulation& simulation) {
    return std::make_unique<SimulationImages>(simulation, renderer);
  };
}

}  // namespace bullet_sim
