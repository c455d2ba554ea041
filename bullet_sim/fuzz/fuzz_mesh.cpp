// libFuzzer target for the mesh importer (assimp, then ours): the first byte chooses the format (STL, OBJ or
// COLLADA, Gazebo's), the rest is the file. importMesh must return the mesh (its embedded images decoded) or
// an error, never crash, hang or touch memory it does not own. It imports in this process, where the fuzzer
// sees what it covers; the simulator imports in a child process (loadMesh), so that what crashes assimp here
// is a load error there.
// Built and run by scripts/fuzz.sh.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "bullet_sim/assets/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".stl", ".obj", ".dae"};
  const std::string extension = kExtensions[data[0] % 3];
  const char* tmpdir = std::getenv("TMPDIR");
  std::string path = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/fuzz_mesh_XXXXXX" + extension;
  const int fd = mkstemps(path.data(), static_cast<int>(extension.size()));
  if (fd < 0) abort();  // the fuzzer cannot work without a file
  const bool written = write(fd, data + 1, size - 1) == static_cast<ssize_t>(size - 1);
  close(fd);
  if (written) {
    std::string error;
    std::vector<std::string> warnings;
    bullet_sim::TextureCache textures;  // embedded images are decoded too
    bullet_sim::importMesh(path, Eigen::Vector3d::Ones(), &error, &textures, &warnings);
  }
  unlink(path.c_str());
  return 0;
}
