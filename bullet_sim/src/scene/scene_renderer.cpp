#include "bullet_sim/scene/scene_renderer.h"

#include <cstring>

namespace bullet_sim {

void dropAlpha(const uint8_t* rgba, size_t pixels, std::vector<uint8_t>& rgb) {
  rgb.resize(pixels * 3);
  if (pixels == 0) return;
  uint8_t* out = rgb.data();
  // Four bytes at a time: each pixel's alpha lands where the next pixel's red then goes.
  for (size_t p = 0; p + 1 < pixels; ++p, rgba += 4, out += 3) std::memcpy(out, rgba, 4);
  std::memcpy(out, rgba, 3);
}

void SceneRenderer::renderRgb(const Scene& scene, int width, int height, std::vector<uint8_t>& rgb,
                              std::vector<float>* depth) {
  const Image image = render(scene, width, height, depth);
  dropAlpha(image.rgba.data(), image.rgba.size() / 4, rgb);
}

}  // namespace bullet_sim
