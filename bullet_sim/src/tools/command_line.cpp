#include "tools/command_line.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "bullet_sim/description/world_spec.h"

extern char** environ;

namespace bullet_sim {

double parseNumber(const std::string& text, const std::string& option) {
  size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value)) {
    throw UsageError(option + ": [" + text + "] is not a number");
  }
  return value;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::istringstream stream(text);
  for (std::string part; std::getline(stream, part, separator);) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

std::string runXacro(const std::string& file, const std::vector<std::string>& args) {
  std::vector<std::string> command = {"xacro", file};
  command.insert(command.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& word : command) argv.push_back(word.data());
  argv.push_back(nullptr);

  int pipe_fds[2];
  if (pipe(pipe_fds) != 0)
    throw Failure(std::string("cannot create a pipe for xacro: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "xacro", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_fds[1]);
  if (spawned != 0) {
    close(pipe_fds[0]);
    throw Failure(
        std::string("cannot run xacro: ") + std::strerror(spawned) +
        "; install it (scripts/workspace.sh install) and put it on PATH, or pass an expanded .urdf");
  }
  std::string urdf;
  char buffer[65536];
  for (ssize_t n; (n = read(pipe_fds[0], buffer, sizeof buffer)) != 0;) {
    if (n > 0)
      urdf.append(buffer, n);
    else if (errno != EINTR)
      break;
  }
  close(pipe_fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Failure("xacro " + file + " failed (see its message above)");
  }
  return urdf;
}

std::string readUrdfFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Failure("cannot read URDF [" + path + "]: " + std::strerror(errno));
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string findWorld(const std::string& name, const PackageResolver& resolver) {
  std::string error;
  const auto path = findWorldFile(name.empty() ? "empty.world" : name, resolver, &error);
  if (!path)
    throw Failure(error + "; pass an existing file, or source devel/setup.bash for ROS_PACKAGE_PATH");
  return *path;
}

}  // namespace bullet_sim
