// A fixed pool of threads that runs independent tasks side by side: a step's (each robot's lidar scans, each
// robot's wheels) and a spawn's (each mesh's CoACD process). Each task writes only its own results, so the
// order the threads take them in never shows: whoever merges them does so in task order, and reruns stay
// bit-identical. A lane runs jobs behind the caller's back, one after another in the order they were started:
// the scans due in a step while the next steps' physics runs.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace bullet_sim {

class WorkPool {
 public:
  /// `threads` in all, the calling thread included: threads - 1 are started here and sleep between batches.
  /// 1 (or less) runs every task on the caller.
  explicit WorkPool(int threads);
  ~WorkPool();
  WorkPool(const WorkPool&) = delete;
  WorkPool& operator=(const WorkPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  /// Runs task(0) ... task(count - 1), each once, on the pool's threads and the caller's; returns when all
  /// are done. If tasks throw, the exception of the lowest-numbered one is rethrown here. A thread takes
  /// consecutive tasks a chunk at a time (about a quarter of its share), so that a hundred robots' small
  /// tasks cost a few handovers of the pool's lock, not two each.
  void run(size_t count, const std::function<void(size_t)>& task);

 private:
  static constexpr size_t kChunksPerThread = 4;

  void work();
  /// Takes tasks of the current batch until none is left.
  void drain();

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(size_t)>* task_ = nullptr;
  size_t count_ = 0;
  size_t next_ = 0;        ///< the next task to hand out
  size_t chunk_ = 1;       ///< tasks handed out at once
  size_t unfinished_ = 0;  ///< tasks handed out or not, not yet done
  uint64_t batch_ = 0;     ///< counts batches, so a worker wakes once per batch
  bool stopping_ = false;
  size_t failed_task_ = 0;
  std::exception_ptr failure_;
  std::vector<std::thread> workers_;
};

/// One thread that runs jobs one after another, in the order they were started, while the caller goes on.
/// Only one thread may start and wait.
class WorkLane {
 public:
  using Ticket = uint64_t;  ///< a job's number: 1 for the first started

  WorkLane();
  /// Waits for the jobs started, and stops the thread.
  ~WorkLane();
  WorkLane(const WorkLane&) = delete;
  WorkLane& operator=(const WorkLane&) = delete;

  /// Queues `job` behind the jobs started before it.
  Ticket start(std::function<void()> job);
  /// Whether job `ticket`, and so every job before it, has ended.
  bool finished(Ticket ticket) const { return ended_.load(std::memory_order_acquire) >= ticket; }
  /// Whether every job started has ended, so that wait() returns at once.
  bool finished() const { return finished(started_); }
  /// Waits for job `ticket` and those before it to end, and rethrows the first failure among them not yet
  /// rethrown.
  void wait(Ticket ticket);
  /// Waits for every job started.
  void wait() { wait(started_); }

 private:
  void work();

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<std::function<void()>> jobs_;  ///< started, not yet taken by the thread
  Ticket started_ = 0;                      ///< the caller's count of jobs started
  std::atomic<Ticket> ended_{0};            ///< jobs ended, in order
  bool stopping_ = false;
  Ticket failed_ = 0;  ///< the first job whose failure is not yet rethrown; 0: none
  std::exception_ptr failure_;
  std::thread thread_;
};

/// The threads a simulation's pool takes when not told: the cores the calling thread may run on (its
/// affinity: one under `taskset -c 0`), at most `most`.
int defaultPoolThreads(int most = 4);

}  // namespace bullet_sim
