// What cameras see in a running simulation: the world and every robot (the camera's own included, as in
// Gazebo) at their current link poses, in their colours, drawn by a SceneRenderer. It keeps the tessellated
// shapes between frames, so the renderer uploads each shape once.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/plugins/image_source.h"
#include "bullet_sim/scene/scene.h"
#include "bullet_sim/scene/scene_renderer.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

/// The renderer to draw with, made when first asked for: a simulation whose cameras nobody watches never
/// creates one.
using RendererAccess = std::function<SceneRenderer&()>;

class SimulationImages final : public ImageSource {
 public:
  SimulationImages(const Simulation& simulation, RendererAccess renderer);

  void render(const ImageRequest& request, RenderedImage& image) override;

  /// The scene a camera at `request` sees, without drawing it.
  const Scene& sceneFor(const ImageRequest& request);

 private:
  struct LinkVisuals {
    std::string link;
    std::vector<SceneMesh> meshes;  ///< poses in the link frame
  };
  struct RobotVisuals {
    const PhysicsRobot* body = nullptr;  ///< the robot they were made for; a respawn makes new ones
    std::vector<LinkVisuals> links;      ///< the links that have visuals
  };

  /// Brings the robots' visuals up to date with the simulation's robots.
  void refreshRobots();

  const Simulation& simulation_;
  RendererAccess renderer_;
  Scene scene_;
  /// A world model's visual: which one, and its origin in the model frame.
  struct WorldVisual {
    size_t model, index;
    Eigen::Isometry3d origin;
  };
  /// scene_.meshes starts with the world's visuals.
  std::vector<WorldVisual> world_visuals_;
  std::map<std::string, RobotVisuals> robots_;
};

/// SimulationOptions::images for a simulation whose cameras draw with `renderer`.
ImageSourceFactory imagesFrom(RendererAccess renderer);

}  // namespace bullet_sim
