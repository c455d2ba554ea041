// The render library's entry points for a program that loads it only when it first draws (the simulator
// node, with dlopen): OSMesa brings LLVM, 50 MB and 50 ms of start-up that most runs never need.
#include "bullet_sim/render/image.h"
#include "bullet_sim/render/offscreen_renderer.h"

extern "C" {

/// A new OffscreenRenderer, owned by the caller; nullptr, with `error` set, when OSMesa cannot make one.
bullet_sim::SceneRenderer* bullet_sim_new_renderer(std::string* error) {
  try {
    return std::make_unique<bullet_sim::OffscreenRenderer>().release();
  } catch (const std::exception& e) {
    *error = e.what();
    return nullptr;
  }
}

/// writePng.
bool bullet_sim_write_png(const std::string* path, const bullet_sim::Image* image, std::string* error) {
  return bullet_sim::writePng(*path, *image, error);
}
}
