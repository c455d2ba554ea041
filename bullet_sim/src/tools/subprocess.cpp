#include "bullet_sim/tools/subprocess.h"

#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace bullet_sim {

namespace {

/// Reads both pipes until the child closes them; both are drained together, since a child blocked on a full
/// stderr would never close its stdout.
void drain(int out_fd, int err_fd, ProcessOutput& output) {
  pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  std::string* sinks[2] = {&output.output, &output.errors};
  for (int open = 2; open > 0;) {
    if (poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !fds[i].revents) continue;
      char buffer[65536];
      const ssize_t n = read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        sinks[i]->append(buffer, n);
      } else if (n == 0 || errno != EINTR) {
        fds[i].fd = -1;  // poll ignores negative descriptors
        --open;
      }
    }
  }
}

}  // namespace

std::optional<ProcessOutput> runProcess(const std::vector<std::string>& command, std::string* error) {
  if (command.empty()) {
    *error = "no command to run";
    return std::nullopt;
  }
  std::vector<std::string> words = command;
  std::vector<char*> argv;
  for (auto& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  int out_pipe[2], err_pipe[2];
  if (pipe(out_pipe) != 0 || pipe(err_pipe) != 0) {
    *error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return std::nullopt;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], STDERR_FILENO);
  for (int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1]})
    posix_spawn_file_actions_addclose(&actions, fd);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(out_pipe[1]);
  close(err_pipe[1]);
  ProcessOutput output;
  if (spawned == 0) drain(out_pipe[0], err_pipe[0], output);
  close(out_pipe[0]);
  close(err_pipe[0]);
  if (spawned != 0) {
    *error = "cannot run " + command.front() + ": " + std::strerror(spawned);
    return std::nullopt;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  output.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return output;
}

std::string expandXacro(const std::string& file, const std::vector<std::string>& args) {
  std::vector<std::string> command = {"xacro", file};
  command.insert(command.end(), args.begin(), args.end());
  std::string error;
  const auto xacro = runProcess(command, &error);
  if (!xacro) {
    throw std::runtime_error(error +
                             "; install xacro (scripts/workspace.sh install) and put it on PATH, or "
                             "pass an expanded URDF");
  }
  if (xacro->status != 0) {
    throw std::runtime_error(
        "xacro " + file + " failed: " + xacro->errors.substr(0, xacro->errors.find_last_not_of(" \n") + 1));
  }
  return xacro->output;
}

}  // namespace bullet_sim
