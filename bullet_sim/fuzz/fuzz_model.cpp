// libFuzzer target for the robot description parser (URDF with <gazebo> tags) and urdf_doctor's checks:
// whatever the bytes, both must return or throw SpecError, never crash, hang or touch memory they do not own.
// Built and run by scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/plugins/registry.h"
#include "bullet_sim/doctor/doctor.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string urdf(reinterpret_cast<const char*>(data), size);
  // No search path: package:// URIs fail to resolve, so inputs never read mesh files from the workspace.
  const bullet_sim::PackageResolver resolver(std::vector<std::string>{});
  try {
    bullet_sim::parseModel(urdf, "fuzz.urdf", resolver);
  } catch (const bullet_sim::SpecError&) {
    // A rejected file is a correct answer.
  }
  bullet_sim::examineUrdf(urdf, "fuzz.urdf", resolver).text();
  return 0;
}
