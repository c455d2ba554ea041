// The step's pool of threads: every task runs once, whatever the threads; a task's failure reaches the
// caller.
// The lane: a job runs on its own thread while the caller goes on, and its failure reaches whoever waits.
#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "src/common/work_pool.h"

namespace bullet_sim {
namespace {

TEST(WorkPool, RunsEveryTaskOnceOnAsManyThreadsAsItWasGiven) {
  for (const int threads : {1, 2, 3}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    WorkPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    for (const size_t count : {0, 1, 7, 100}) {  // several batches through the same threads
      std::vector<std::atomic<int>> runs(count);
      pool.run(count, [&](size_t k) { ++runs[k]; });
      for (size_t k = 0; k < count; ++k) EXPECT_EQ(runs[k], 1) << "task " << k;
    }
  }
}

TEST(WorkPool, TasksRunSideBySideOnItsThreads) {
  WorkPool pool(2);
  // Each of two tasks waits (bounded) for the other to start: only two threads at once let both see it.
  std::atomic<int> started{0};
  std::atomic<int> met{0};
  pool.run(2, [&](size_t) {
    ++started;
    for (int i = 0; i < 2000000 && started < 2; ++i) std::this_thread::yield();
    if (started == 2) ++met;
  });
  EXPECT_EQ(met, 2);
}

TEST(WorkPool, TheLowestFailingTaskIsRethrownOnceAllAreDone) {
  WorkPool pool(2);
  std::atomic<int> done{0};
  try {
    pool.run(10, [&](size_t k) {
      ++done;
      if (k == 3 || k == 8) throw std::runtime_error("task " + std::to_string(k));
    });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "task 3");
  }
  EXPECT_EQ(done, 10);
  std::atomic<int> after{0};
  pool.run(3, [&](size_t) { ++after; });  // the pool still works; the caller's thread may take all three
  EXPECT_EQ(after, 3);
}

TEST(WorkPool, AmongManyTasksTakenInChunksTheLowestFailingOneIsRethrown) {
  WorkPool pool(2);
  std::vector<std::atomic<int>> runs(100);
  try {
    pool.run(100, [&](size_t k) {  // 30 and 31 share a chunk; 37 is in the next
      ++runs[k];
      if (k == 31 || k == 37 || k == 30) throw std::runtime_error("task " + std::to_string(k));
    });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "task 30");
  }
  for (size_t k = 0; k < runs.size(); ++k) EXPECT_EQ(runs[k], 1) << "task " << k;
}

// A run pinned to one core (a sweep's taskset) takes one thread; unpinned, the cores it may use, at most 4.
TEST(WorkPool, TakesTheCoresItsThreadMayRunOn) {
  cpu_set_t all;
  ASSERT_EQ(sched_getaffinity(0, sizeof(all), &all), 0);
  int first = 0;
  while (!CPU_ISSET(first, &all)) ++first;
  int pinned = 0, unpinned = 0;
  std::thread probe([&] {  // its own thread, so that the test's affinity stays as it was
    unpinned = defaultPoolThreads();
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    pinned = sched_setaffinity(0, sizeof(one), &one) == 0 ? defaultPoolThreads() : -1;
  });
  probe.join();
  if (pinned == -1) GTEST_SKIP() << "this process may not pin a thread to one core";
  EXPECT_EQ(unpinned, std::min(CPU_COUNT(&all), 4));
  EXPECT_EQ(pinned, 1);
  EXPECT_EQ(defaultPoolThreads(1), 1);
}

TEST(WorkLane, RunsJobsInTheOrderStartedOnItsOwnThreadWhileTheCallerGoesOn) {
  WorkLane lane;
  EXPECT_TRUE(lane.finished());
  lane.wait();  // nothing started: returns at once
  std::atomic<bool> release{false};
  std::thread::id ran_on;
  std::vector<int> order;  // written by the lane's thread only, read after wait()
  const WorkLane::Ticket first = lane.start([&] {
    ran_on = std::this_thread::get_id();
    for (int i = 0; i < 20000000 && !release; ++i) std::this_thread::yield();  // bounded
    order.push_back(1);
  });
  const WorkLane::Ticket second = lane.start([&] { order.push_back(2); });  // queued behind the first
  EXPECT_LT(first, second);
  EXPECT_FALSE(lane.finished(first));  // the job waits for the caller, which went on
  EXPECT_FALSE(lane.finished());
  release = true;
  lane.wait(first);
  EXPECT_TRUE(lane.finished(first));
  lane.wait();
  EXPECT_TRUE(lane.finished(second));
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
  EXPECT_NE(ran_on, std::this_thread::get_id());
}

TEST(WorkLane, AJobsFailureIsRethrownOnceByTheFirstWaitThatCoversIt) {
  WorkLane lane;
  std::atomic<bool> release{false};
  const WorkLane::Ticket before = lane.start([&] {
    for (int i = 0; i < 20000000 && !release; ++i) std::this_thread::yield();  // bounded
  });
  const WorkLane::Ticket failing = lane.start([] { throw std::runtime_error("the job"); });
  int after = 0;
  lane.start([&] { after = 3; });  // the lane goes on after a failure
  release = true;
  EXPECT_NO_THROW(lane.wait(before));  // the failure came later
  try {
    lane.wait(failing);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "the job");
  }
  EXPECT_NO_THROW(lane.wait());  // the failure is delivered once
  EXPECT_EQ(after, 3);
}

TEST(WorkLane, ItsDestructorWaitsForEveryJobStarted) {
  std::atomic<int> done{0};
  {
    WorkLane lane;
    for (int job = 0; job < 3; ++job) {
      lane.start([&] {
        for (int i = 0; i < 1000; ++i) std::this_thread::yield();
        ++done;
      });
    }
  }
  EXPECT_EQ(done, 3);
}

}  // namespace
}  // namespace bullet_sim
