// libFuzzer target for the SDF readers (libsdformat, then ours), of worlds and of models to spawn: whatever
// the bytes, each must return or throw SpecError, never crash, hang or touch memory it does not own. They
// read in this process (parseWorldHere, readSdfModelHere), where the fuzzer sees what they cover; the
// simulator reads in a child process. Built and run by scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/world.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string sdf(reinterpret_cast<const char*>(data), size);
  // No search path: package:// URIs fail to resolve, so inputs never read files from the workspace.
  const bullet_sim::PackageResolver resolver(std::vector<std::string>{});
  try {
    bullet_sim::parseWorldHere(sdf, "/nonexistent/fuzz.world", resolver, nullptr);
  } catch (const bullet_sim::SpecError&) {
    // A rejected file is a correct answer.
  }
  try {
    bullet_sim::readSdfModelHere(sdf, "/nonexistent/fuzz.sdf", resolver, nullptr);
  } catch (const bullet_sim::SpecError&) {
  }
  return 0;
}
