#include "bullet_sim/tools/run_recorder.h"

#include <dlfcn.h>

#include <stdexcept>

namespace bullet_sim {

namespace {
constexpr char kLibrary[] = "libbullet_sim_bag.so";  // found through the tool's RUNPATH or LD_LIBRARY_PATH
}

std::unique_ptr<RunRecorder> loadBagRecorder(const BagSettings& settings, RecorderErrors errors) {
  void* library = dlopen(kLibrary, RTLD_NOW | RTLD_LOCAL);
  if (!library)
    throw std::runtime_error("cannot load the bag recorder (" + std::string(kLibrary) + "): " + dlerror());
  // Returns the recorder, or nullptr with `error` saying which setting is wrong.
  using NewRecorder = RunRecorder* (*)(const BagSettings*, const RecorderErrors*, std::string*);
  const auto make = reinterpret_cast<NewRecorder>(dlsym(library, "bullet_sim_new_bag_recorder"));
  if (!make)
    throw std::runtime_error("cannot load the bag recorder (" + std::string(kLibrary) + "): no entry point");
  std::string error;
  std::unique_ptr<RunRecorder> recorder(make(&settings, &errors, &error));
  if (!recorder) throw std::invalid_argument(error);
  return recorder;
}

}  // namespace bullet_sim
