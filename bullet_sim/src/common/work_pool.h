// A fixed pool of threads that runs independent tasks side by side: a step's (each robot's lidar scans, each
// robot's wheels) and a spawn's (each mesh's CoACD process). Each task writes only its own results, so the
// order the threads take them in never shows: whoever merges them does so in task order, and reruns stay
// bit-identical. A lane runs one job behind the caller's back: a step's scans while the next steps' physics
// runs.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
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

/// One thread that runs one job at a time while the caller goes on.
class WorkLane {
 public:
  WorkLane();
  /// Waits for the job, if one runs, and stops the thread.
  ~WorkLane();
  WorkLane(const WorkLane&) = delete;
  WorkLane& operator=(const WorkLane&) = delete;

  /// Starts `job` on the lane's thread. Throws std::logic_error while the last job is not waited for.
  void start(std::function<void()> job);
  /// Whether the job started last has ended, so that wait() returns at once.
  bool finished() const { return finished_.load(std::memory_order_acquire); }
  /// Waits for the job started last to end, and rethrows what it threw; returns at once without one.
  void wait();

 private:
  void work();

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void()> job_;
  bool started_ = false;  ///< a job was started and not yet waited for
  bool stopping_ = false;
  std::atomic<bool> finished_{true};
  std::exception_ptr failure_;
  std::thread thread_;
};

/// The threads a simulation's pool takes when not told: the cores the calling thread may run on (its
/// affinity: one under `taskset -c 0`), at most `most`.
int defaultPoolThreads(int most = 4);

}  // namespace bullet_sim
