// urdf_doctor FILE [name:=value ...]: says what in a URDF or xacro makes the simulation misbehave, and how to
// fix it. Exit status 0 when clean or warnings only, 1 on errors, 2 when the file cannot be read, expanded or
// parsed. ROS-free: it needs ROS_PACKAGE_PATH for package:// URIs and the xacro executable for .xacro files.
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/tools/doctor.h"

extern char** environ;

namespace bullet_sim {
namespace {

constexpr char kUsage[] =
    "usage: urdf_doctor FILE [name:=value ...]\n"
    "\n"
    "Checks a URDF, or a .xacro expanded with the xacro executable and the name:=value arguments, and\n"
    "reports each problem with the element, the reason and the fix.\n"
    "Exit status: 0 clean or warnings only, 1 errors, 2 the file cannot be read, expanded or parsed.\n";

struct Output {
  int status = -1;  ///< exit status, or -1 when the program did not exit normally
  std::string out;
  std::string err;
};

/// Runs `command` (looked up on PATH) and collects what it prints; nullopt with `error` set when it cannot
/// start.
std::optional<Output> runProgram(std::vector<std::string> command, std::string* error) {
  std::vector<char*> argv;
  for (auto& word : command) argv.push_back(word.data());
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

  Output output;
  // Both pipes are drained together: a child blocked on a full stderr would never close its stdout.
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&output.out, &output.err};
  for (int open = spawned == 0 ? 2 : 0; open > 0;) {
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

bool endsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

DoctorReport examineFile(const std::string& file, const std::vector<std::string>& args) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  std::ifstream in(file);
  if (!in) return unreadableReport(file, "cannot read the file: " + std::string(std::strerror(errno)));
  if (!endsWith(file, ".xacro") && args.empty())
    return examineUrdf(std::string(std::istreambuf_iterator<char>(in), {}), file, resolver);

  std::vector<std::string> command = {"xacro", file};
  command.insert(command.end(), args.begin(), args.end());
  std::string error;
  const std::optional<Output> xacro = runProgram(command, &error);
  if (!xacro) {
    return unreadableReport(file,
                            error + "; install xacro (scripts/workspace.sh install) and put it on PATH");
  }
  if (xacro->status != 0) {
    const std::string message = xacro->err.substr(0, xacro->err.find_last_not_of(" \n") + 1);
    return unreadableReport(file, "xacro failed: " + message);
  }
  return examineUrdf(xacro->out, file, resolver);
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  const std::vector<std::string> words(argv + 1, argv + argc);
  if (!words.empty() && (words.front() == "-h" || words.front() == "--help")) {
    std::cout << bullet_sim::kUsage;
    return 0;
  }
  const bool args_ok = std::all_of(words.begin() + std::min<size_t>(1, words.size()), words.end(),
                                   [](const std::string& w) { return w.find(":=") != std::string::npos; });
  if (words.empty() || !args_ok) {
    std::cerr << bullet_sim::kUsage;
    return 2;
  }
  const bullet_sim::DoctorReport report =
      bullet_sim::examineFile(words.front(), std::vector<std::string>(words.begin() + 1, words.end()));
  std::cout << report.text();
  return report.exitCode();
}
