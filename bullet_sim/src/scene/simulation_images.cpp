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
    for (const Visual& visual : world.models[m].visuals) {
      world_visuals_.emplace_back(m, visual.origin);
      scene_.meshes.push_back({tessellate(visual.shape), visual.origin, visual.rgba});
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
      for (const Visual& visual : link.visuals) {
        entry.visuals.push_back({link.name, visual.origin, tessellate(visual.shape), visual.rgba});
      }
    }
  }
}

const Scene& SimulationImages::sceneFor(const ImageRequest& request) {
  refreshRobots();
  scene_.meshes.resize(world_visuals_.size());
  for (size_t k = 0; k < world_visuals_.size(); ++k) {  // the world API may have moved world models
    scene_.meshes[k].pose = simulation_.worldModelPose(world_visuals_[k].first) * world_visuals_[k].second;
  }
  for (const auto& [name, robot] : robots_) {
    std::map<std::string, Eigen::Isometry3d> link_poses;
    for (const RobotVisual& visual : robot.visuals) {
      auto pose = link_poses.find(visual.link);
      if (pose == link_poses.end()) pose = link_poses.emplace(visual.link, robot.body->linkPose(visual.link)).first;
      scene_.meshes.push_back({visual.mesh, pose->second * visual.origin, visual.rgba});
    }
  }
  scene_.camera = requestCamera(request);
  return scene_;
}

RenderedImage SimulationImages::render(const ImageRequest& request) {
  const Scene& scene = sceneFor(request);
  RenderedImage rendered;
  const Image image =
      renderer_().render(scene, request.width, request.height, request.depth ? &rendered.depth : nullptr);
  rendered.width = image.width;
  rendered.height = image.height;
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  rendered.rgb.resize(pixels * 3);
  for (size_t p = 0; p < pixels; ++p) {
    for (size_t c = 0; c < 3; ++c) rendered.rgb[p * 3 + c] = image.rgba[p * 4 + c];
  }
  return rendered;
}

ImageSourceFactory imagesFrom(RendererAccess renderer) {
  return [renderer](const Simulation& simulation) {
    return std::make_unique<SimulationImages>(simulation, renderer);
  };
}


}  // namespace bullet_sim
