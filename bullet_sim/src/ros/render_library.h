// The renderer of the simulator node, loaded (with OSMesa and LLVM behind it) only when first used: most
// runs take no snapshot and subscribe to no camera, and start faster and smaller without it.
#pragma once

#include <memory>
#include <string>

#include "bullet_sim/scene/image.h"
#include "bullet_sim/scene/scene_renderer.h"

namespace bullet_sim {

class RenderLibrary {
 public:
  /// The renderer, loading libbullet_sim_render.so first if need be. Throws std::runtime_error saying why
  /// when it cannot be loaded.
  SceneRenderer& renderer();
  /// writePng of the render library; false with `error` when it cannot be loaded or the file written.
  bool writePng(const std::string& path, const Image& image, std::string* error);

 private:
  void load();

  using WritePng = bool (*)(const std::string*, const Image*, std::string*);
  WritePng write_png_ = nullptr;
  std::unique_ptr<SceneRenderer> renderer_;  ///< made by the library, which is never unloaded
};

}  // namespace bullet_sim
