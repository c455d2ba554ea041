#include "assets/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>

namespace bullet_sim {

namespace {

constexpr char kReturned = 'R';
constexpr char kThrew = 'T';

/// Bytes of address space this process has mapped, from /proc/self/statm; 0 when it cannot tell.
size_t mappedBytes() {
  std::ifstream statm("/proc/self/statm");
  size_t pages = 0;
  statm >> pages;
  return pages * static_cast<size_t>(sysconf(_SC_PAGESIZE));
}

bool writeAll(int fd, const std::string& data) {
  for (size_t written = 0; written < data.size();) {
    const ssize_t n = write(fd, data.data() + written, data.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    written += static_cast<size_t>(n);
  }
  return true;
}

[[noreturn]] void childMain(int fd, const std::function<std::string()>& work, size_t address_space,
                            double seconds) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);  // an orphan would import on for nobody
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);
  const rlimit memory{address_space, address_space};
  setrlimit(RLIMIT_AS, &memory);
  const rlim_t cpu = static_cast<rlim_t>(seconds) + 1;  // a backstop to the parent's wall-clock limit
  const rlimit cpu_time{cpu, cpu};
  setrlimit(RLIMIT_CPU, &cpu_time);
  std::string message;
  try {
    message = kReturned + work();
  } catch (const std::bad_alloc&) {
    message = std::string(1, kThrew) + "it needs more memory than its limit";
  } catch (const std::exception& e) {
    message = kThrew + std::string(e.what());
  } catch (...) {
    message = std::string(1, kThrew) + "an unknown exception";
  }
  _exit(writeAll(fd, message) ? 0 : 1);
}

/// Reads the child's message until it closes the pipe or `deadline` passes; false when it passed.
bool readUntil(int fd, std::chrono::steady_clock::time_point deadline, std::string& into) {
  char buffer[1 << 16];
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd ready{fd, POLLIN, 0};
    const int polled = poll(&ready, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (polled < 0 && errno != EINTR) return true;
    if (polled <= 0) continue;
    const ssize_t n = read(fd, buffer, sizeof(buffer));
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) return true;
    into.append(buffer, static_cast<size_t>(n));
  }
}

}  // namespace

ChildOutcome runInChild(const std::function<std::string()>& work, size_t extra_memory, double seconds) {
  ChildOutcome outcome;
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    outcome.why = std::string("cannot create a pipe: ") + std::strerror(errno);
    return outcome;
  }
  const size_t address_space = mappedBytes() + extra_memory;
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
  const pid_t child = fork();
  if (child < 0) {
    outcome.why = std::string("cannot start a process: ") + std::strerror(errno);
    close(fds[0]);
    close(fds[1]);
    return outcome;
  }
  if (child == 0) {
    close(fds[0]);
    childMain(fds[1], work, address_space, seconds);
  }
  close(fds[1]);
  std::string message;
  const bool in_time = readUntil(fds[0], deadline, message);
  close(fds[0]);
  if (!in_time) kill(child, SIGKILL);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!in_time) {
    outcome.ending = ChildOutcome::Ending::kTimedOut;
  } else if (WIFSIGNALED(status)) {
    outcome.ending = ChildOutcome::Ending::kCrashed;
    const int signal = WTERMSIG(status);
    outcome.why = std::string("signal ") + std::to_string(signal) + " (" + strsignal(signal) + ")" +
                  (signal == SIGXCPU ? ", out of CPU time" : "");
  } else if (!message.empty() && message.front() == kReturned) {
    outcome.ending = ChildOutcome::Ending::kReturned;
    outcome.output = message.substr(1);
  } else if (!message.empty() && message.front() == kThrew) {
    outcome.ending = ChildOutcome::Ending::kThrew;
    outcome.why = message.substr(1);
  } else {
    outcome.ending = ChildOutcome::Ending::kCrashed;
    outcome.why = "it exited with status " + std::to_string(WEXITSTATUS(status)) + " and no answer";
  }
  return outcome;
}

}  // namespace bullet_sim
