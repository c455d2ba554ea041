#include "exit_guard.h"

#include <ros/ros.h>
#include <semaphore.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>

namespace bullet_sim {

namespace {

// A signal handler can only reach a global, and may only post a semaphore.
sem_t signalled;

void onSignal(int) { sem_post(&signalled); }

void writeError(const char* text) {
  const ssize_t ignored = write(STDERR_FILENO, text, strlen(text));
  (void)ignored;
}

}  // namespace

struct ExitGuard::Watch {
  double grace_seconds;
  std::mutex mutex;
  std::condition_variable done_changed;
  bool done = false;  ///< the guard is gone: the process ends by itself

  /// Waits for a signal (or the guard's end), asks ROS to shut down, then grants the grace period.
  void run() {
    while (sem_wait(&signalled) != 0 && errno == EINTR) {
    }
    std::unique_lock<std::mutex> lock(mutex);
    if (done) return;
    ros::requestShutdown();
    const auto grace = std::chrono::duration<double>(grace_seconds);
    if (done_changed.wait_for(lock, grace, [this] { return done; })) return;
    writeError("simulator: still busy after SIGINT or SIGTERM: exiting now\n");
    _exit(130);
  }
};

ExitGuard::ExitGuard(double grace_seconds) : watch_(std::make_shared<Watch>()) {
  watch_->grace_seconds = grace_seconds;
  sem_init(&signalled, 0, 0);
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::thread([watch = watch_] { watch->run(); }).detach();
}

ExitGuard::~ExitGuard() {
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  {
    std::lock_guard<std::mutex> lock(watch_->mutex);
    watch_->done = true;
  }
  watch_->done_changed.notify_all();
  sem_post(&signalled);  // wakes the thread when no signal came
}

}  // namespace bullet_sim
