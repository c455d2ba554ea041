// The renderer as the scene layer sees it: what draws a Scene. render/offscreen_renderer.h implements it; the
// scene layer's image sources draw through it without depending on the render layer.
#pragma once

#include <cstdint>
#include <vector>

#include "bullet_sim/scene/image.h"
#include "bullet_sim/scene/scene.h"

namespace bullet_sim {

class SceneRenderer {
 public:
  virtual ~SceneRenderer() = default;
  /// Draws `scene` into a width x height image, top row first. When `depth` is given, it is filled with each
  /// pixel's distance along the view axis [m], rows top first; +inf where nothing was drawn. Throws
  /// std::invalid_argument for a size it cannot render.
  virtual Image render(const Scene& scene, int width, int height, std::vector<float>* depth = nullptr) = 0;

  /// As render, into `rgb` (3 bytes per pixel, rows top first) and `depth`, whose storage is reused from
  /// call to call: a camera that renders every frame allocates nothing. The default converts render()'s.
  virtual void renderRgb(const Scene& scene, int width, int height, std::vector<uint8_t>& rgb,
                         std::vector<float>* depth = nullptr);
};

}  // namespace bullet_sim
