// Reading the files a description names (URDF, SDF, meshes, an OBJ's .mtl): regular files only, of bounded
// size. A FIFO would block the reader for ever, /dev/zero would fill the memory.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace bullet_sim {

/// Why the file at `path` may not be read: it cannot be opened, it is not a regular file (a directory, a
/// FIFO, a device, a socket), or it has more than `max_bytes` (the limit called `limit_name`). nullopt when
/// it may.
std::optional<std::string> fileProblem(const std::string& path, size_t max_bytes, const char* limit_name);

/// The same for a file already opened as `fd`, so that nothing can swap the file between check and read.
std::optional<std::string> openedFileProblem(int fd, size_t max_bytes, const char* limit_name);

/// The whole of a regular file of at most `max_bytes`; std::runtime_error "[path] <problem>" otherwise.
/// It never blocks on a FIFO.
std::string readRegularFile(const std::string& path, size_t max_bytes, const char* limit_name);

}  // namespace bullet_sim
