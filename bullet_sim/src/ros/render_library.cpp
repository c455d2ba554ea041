#include "render_library.h"

#include <dlfcn.h>

#include <stdexcept>

namespace bullet_sim {

namespace {
constexpr char kLibrary[] = "libbullet_sim_render.so";  // found through the node's RUNPATH or LD_LIBRARY_PATH
}

void RenderLibrary::load() {
  if (renderer_) return;
  void* library = dlopen(kLibrary, RTLD_NOW | RTLD_LOCAL);
  const auto fail = [](const std::string& why) {
    throw std::runtime_error("cannot load the renderer (" + std::string(kLibrary) + "): " + why);
  };
  if (!library) fail(dlerror());
  using NewRenderer = SceneRenderer* (*)(std::string*);
  const auto make = reinterpret_cast<NewRenderer>(dlsym(library, "bullet_sim_new_renderer"));
  write_png_ = reinterpret_cast<WritePng>(dlsym(library, "bullet_sim_write_png"));
  if (!make || !write_png_) fail("it lacks its entry points");
  std::string error;
  renderer_.reset(make(&error));
  if (!renderer_) fail(error);
}

SceneRenderer& RenderLibrary::renderer() {
  load();
  return *renderer_;
}

bool RenderLibrary::writePng(const std::string& path, const Image& image, std::string* error) {
  try {
    load();
  } catch (const std::runtime_error& e) {
    *error = e.what();
    return false;
  }
  return write_png_(&path, &image, error);
}

}  // namespace bullet_sim
