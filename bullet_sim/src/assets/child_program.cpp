#include "assets/child_program.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

namespace bullet_sim {

namespace {

constexpr size_t kMaxErrors = size_t{64} << 10;

using Clock = std::chrono::steady_clock;

void closeEnd(int& fd) {
  if (fd >= 0) close(fd);
  fd = -1;
}

/// The milliseconds left until `deadline`, at most a second; 0 when it passed.
int millisecondsLeft(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return static_cast<int>(std::clamp<long long>(left, 0, 1000));
}

/// The child's stdin (a socket, so that writing to a child that ended is an error here, not a SIGPIPE),
/// stdout and stderr: [k][0] this process's end, [k][1] the child's.
struct Channels {
  int ends[3][2] = {{-1, -1}, {-1, -1}, {-1, -1}};
  ~Channels() {
    for (auto& pair : ends) {
      closeEnd(pair[0]);
      closeEnd(pair[1]);
    }
  }
  bool open(std::string* why) {
    const bool ok = socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends[0]) == 0 &&
                    pipe2(ends[1], O_CLOEXEC) == 0 && pipe2(ends[2], O_CLOEXEC) == 0;
    if (!ok) *why = std::string("cannot create a pipe: ") + std::strerror(errno);
    return ok;
  }
};

/// The child's side, between fork and exec: only async-signal-safe calls.
[[noreturn]] void execChild(char* const* argv, const Channels& channels, pid_t parent, size_t memory) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(127);  // the parent died before the line above
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);
  const rlimit address_space{memory, memory};
  setrlimit(RLIMIT_AS, &address_space);
  for (int fd = 0; fd < 3; ++fd) {
    if (dup2(channels.ends[fd][1], fd) < 0) _exit(127);
  }
  close_range(3, ~0U, 0);
  execv(argv[0], argv);
  _exit(127);
}

enum class Transfer { kDone, kTimedOut, kTooMuch };

/// Feeds `input` to the child and collects its stdout and stderr until it closes both, `deadline` passes or
/// it writes more than `max_output` bytes.
Transfer exchange(Channels& channels, const std::string& input, Clock::time_point deadline, size_t max_output,
                  ProgramOutcome& outcome) {
  int& to_child = channels.ends[0][0];
  size_t written = 0;
  if (input.empty()) closeEnd(to_child);
  char buffer[1 << 16];
  while (channels.ends[1][0] >= 0 || channels.ends[2][0] >= 0) {
    const int wait = millisecondsLeft(deadline);
    if (wait == 0) return Transfer::kTimedOut;
    pollfd polled[3];
    for (int k = 0; k < 3; ++k) {
      polled[k] = {channels.ends[k][0], static_cast<short>(k ? POLLIN : POLLOUT), 0};
    }
    if (poll(polled, 3, wait) <= 0) continue;
    if (to_child >= 0 && polled[0].revents) {
      const ssize_t n =
          send(to_child, input.data() + written, input.size() - written, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n > 0) written += static_cast<size_t>(n);
      if ((n < 0 && errno != EAGAIN && errno != EINTR) || written == input.size()) closeEnd(to_child);
    }
    for (int k = 1; k < 3; ++k) {
      if (channels.ends[k][0] < 0 || !polled[k].revents) continue;
      const ssize_t n = read(channels.ends[k][0], buffer, sizeof(buffer));
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n <= 0) {
        closeEnd(channels.ends[k][0]);
        continue;
      }
      std::string& into = k == 1 ? outcome.output : outcome.errors;
      if (k == 2 && into.size() >= kMaxErrors) continue;
      into.append(buffer, static_cast<size_t>(n));
      if (k == 1 && into.size() > max_output) return Transfer::kTooMuch;
    }
  }
  return Transfer::kDone;
}

/// Waits for the child to end until `deadline`; false when it passed (a child that closed its output but
/// runs on).
bool endsBefore(pid_t child, Clock::time_point deadline) {
  const int pidfd = static_cast<int>(syscall(SYS_pidfd_open, child, 0));  // glibc 2.36 declares no C linkage
  if (pidfd < 0) return true;  // waitpid below then waits: a kernel without pidfds
  bool ended = false;
  for (int wait; !ended && (wait = millisecondsLeft(deadline)) > 0;) {
    pollfd polled{pidfd, POLLIN, 0};
    ended = poll(&polled, 1, wait) > 0;
  }
  close(pidfd);
  return ended;
}

}  // namespace

ProgramOutcome runProgram(const std::vector<std::string>& command, const std::string& input, size_t memory,
                          double seconds, size_t max_output) {
  ProgramOutcome outcome;
  std::vector<char*> argv;
  for (const std::string& word : command) argv.push_back(const_cast<char*>(word.c_str()));
  argv.push_back(nullptr);
  Channels channels;
  if (!channels.open(&outcome.why)) return outcome;
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  const pid_t parent = getpid();
  const pid_t child = fork();
  if (child == 0) execChild(argv.data(), channels, parent, memory);
  for (auto& pair : channels.ends) closeEnd(pair[1]);
  if (child < 0) {
    outcome.why = std::string("cannot start a process: ") + std::strerror(errno);
    return outcome;
  }
  Transfer transfer = exchange(channels, input, deadline, max_output, outcome);
  if (transfer == Transfer::kDone && !endsBefore(child, deadline)) transfer = Transfer::kTimedOut;
  if (transfer != Transfer::kDone) kill(child, SIGKILL);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (transfer == Transfer::kTimedOut) {
    outcome.ending = ProgramOutcome::Ending::kTimedOut;
  } else if (transfer == Transfer::kTooMuch) {
    outcome.ending = ProgramOutcome::Ending::kCrashed;
    outcome.why = "it wrote more than " + std::to_string(max_output) + " bytes";
  } else if (WIFSIGNALED(status)) {
    outcome.ending = ProgramOutcome::Ending::kCrashed;
    const int signal = WTERMSIG(status);
    outcome.why = std::string("signal ") + std::to_string(signal) + " (" + strsignal(signal) + ")";
  } else {
    outcome.ending = ProgramOutcome::Ending::kExited;
    outcome.status = WEXITSTATUS(status);
  }
  return outcome;
}

}  // namespace bullet_sim
