// Renders a Scene into an RGBA image without a display: OSMesa (Mesa's llvmpipe on the CPU) with OpenGL's
// fixed-function pipeline, one directional light plus ambient, and a depth test.
#pragma once

#include <memory>

#include "bullet_sim/scene/image.h"
#include "bullet_sim/scene/scene.h"
#include "bullet_sim/scene/scene_renderer.h"

namespace bullet_sim {

class OffscreenRenderer final : public SceneRenderer {
 public:
  /// Creates the OSMesa context. Throws std::runtime_error when OSMesa cannot.
  OffscreenRenderer();
  ~OffscreenRenderer() override;
  OffscreenRenderer(OffscreenRenderer&&) noexcept;
  OffscreenRenderer& operator=(OffscreenRenderer&&) noexcept;
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  /// Draws `scene` into a width x height image, top row first, and its depth when asked (SceneRenderer).
  /// The context and its frame buffer are kept for the next render of the same size, and meshes stay on the
  /// GPU while their TriangleMesh lives, so only the first render of a scene pays for uploads. Throws
  /// std::invalid_argument for a size OSMesa cannot render.
  Image render(const Scene& scene, int width, int height, std::vector<float>* depth = nullptr) override;
  /// As render, converting straight into `rgb` (SceneRenderer).
  void renderRgb(const Scene& scene, int width, int height, std::vector<uint8_t>& rgb,
                 std::vector<float>* depth = nullptr) override;

 private:
  class Context;
  /// The context after drawing `scene` and reading its depth into `depth` when given.
  Context& drawn(const Scene& scene, int width, int height, std::vector<float>* depth);
  std::unique_ptr<Context> context_;
};

}  // namespace bullet_sim
