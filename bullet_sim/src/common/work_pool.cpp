#include "common/work_pool.h"

#include <sched.h>

#include <algorithm>
#include <utility>

namespace bullet_sim {

WorkPool::WorkPool(int threads) {
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

WorkPool::~WorkPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void WorkPool::run(size_t count, const std::function<void(size_t)>& task) {
  if (count == 0) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = &task;
    count_ = unfinished_ = count;
    next_ = 0;
    chunk_ = std::max<size_t>(1, count / (kChunksPerThread * static_cast<size_t>(threads())));
    failure_ = nullptr;
    ++batch_;
  }
  if (count > 1) wake_.notify_all();
  drain();
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return unfinished_ == 0; });
  task_ = nullptr;
  if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
}

void WorkPool::work() {
  uint64_t seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || batch_ != seen; });
      if (stopping_) return;
      seen = batch_;
    }
    drain();
  }
}

void WorkPool::drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (task_ && next_ < count_) {
    const size_t first = next_;
    const size_t end = std::min(count_, first + chunk_);
    next_ = end;
    const std::function<void(size_t)>& task = *task_;
    lock.unlock();
    std::exception_ptr failure;
    size_t failed = 0;
    for (size_t index = first; index < end; ++index) {
      try {
        task(index);
      } catch (...) {
        if (!failure) {  // the chunk's lowest
          failure = std::current_exception();
          failed = index;
        }
      }
    }
    lock.lock();
    if (failure && (!failure_ || failed < failed_task_)) {
      failure_ = failure;
      failed_task_ = failed;
    }
    unfinished_ -= end - first;
    if (unfinished_ == 0) done_.notify_all();
  }
}

WorkLane::WorkLane() : thread_([this] { work(); }) {}

WorkLane::~WorkLane() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return finished(); });
    stopping_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

WorkLane::Ticket WorkLane::start(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
  return ++started_;
}

void WorkLane::wait(Ticket ticket) {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this, ticket] { return finished(ticket); });
  if (failure_ && failed_ <= ticket) {
    failed_ = 0;
    std::rethrow_exception(std::exchange(failure_, nullptr));
  }
}

void WorkLane::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stopping, every job ended
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    std::exception_ptr failure;
    try {
      job();
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    const Ticket ended = ended_.load(std::memory_order_relaxed) + 1;
    if (failure && !failure_) {
      failure_ = failure;
      failed_ = ended;
    }
    ended_.store(ended, std::memory_order_release);
    done_.notify_all();
  }
}

int defaultPoolThreads(int most) {
  // The cores this thread may run on: a sweep pins each run to one (taskset), and a container's cpuset may
  // give fewer than the machine has.
  cpu_set_t cores;
  const int usable = sched_getaffinity(0, sizeof(cores), &cores) == 0
                         ? CPU_COUNT(&cores)
                         : static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(usable, 1, std::max(1, most));
}

}  // namespace bullet_sim
