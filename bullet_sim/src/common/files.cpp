#include "bullet_sim/common/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace bullet_sim {

namespace {

std::optional<std::string> statusProblem(const struct stat& status, size_t max_bytes,
                                         const char* limit_name) {
  if (S_ISDIR(status.st_mode)) return "is a directory, not a regular file";
  if (S_ISFIFO(status.st_mode)) return "is a FIFO (a named pipe), not a regular file";
  if (S_ISCHR(status.st_mode) || S_ISBLK(status.st_mode)) return "is a device, not a regular file";
  if (S_ISSOCK(status.st_mode)) return "is a socket, not a regular file";
  if (!S_ISREG(status.st_mode)) return "is not a regular file";
  if (static_cast<size_t>(status.st_size) > max_bytes) {
    return "is " + std::to_string(status.st_size) + " bytes, above the limit of " +
           std::to_string(max_bytes) + " (" + limit_name + ")";
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> fileProblem(const std::string& path, size_t max_bytes, const char* limit_name) {
  struct stat status {};
  if (stat(path.c_str(), &status) != 0) return "cannot be read: " + std::string(std::strerror(errno));
  return statusProblem(status, max_bytes, limit_name);
}

std::optional<std::string> openedFileProblem(int fd, size_t max_bytes, const char* limit_name) {
  struct stat status {};
  if (fstat(fd, &status) != 0) return "cannot be read: " + std::string(std::strerror(errno));
  return statusProblem(status, max_bytes, limit_name);
}

std::string readRegularFile(const std::string& path, size_t max_bytes, const char* limit_name) {
  const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("[" + path + "] cannot be read: " + std::strerror(errno));
  std::optional<std::string> problem = openedFileProblem(fd, max_bytes, limit_name);
  std::string text;
  char buffer[1 << 16];
  while (!problem) {
    const ssize_t n = read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) problem = "cannot be read: " + std::string(std::strerror(errno));
    if (n <= 0) break;
    text.append(buffer, static_cast<size_t>(n));
    if (text.size() > max_bytes) problem = "grew beyond the limit of " + std::to_string(max_bytes) + " bytes";
  }
  close(fd);
  if (problem) throw std::runtime_error("[" + path + "] " + *problem);
  return text;
}

}  // namespace bullet_sim
