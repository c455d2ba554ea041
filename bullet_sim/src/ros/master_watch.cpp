#include "master_watch.h"

#include <ros/master.h>
#include <ros/ros.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace bullet_sim {

namespace {

/// The master's process id, or nullopt when it does not answer.
std::optional<int> masterPid() {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  if (!ros::master::execute("getPid", args, result, payload, /*wait_for_master=*/false)) return std::nullopt;
  if (payload.getType() != XmlRpc::XmlRpcValue::TypeInt) return std::nullopt;
  return static_cast<int>(payload);
}

}  // namespace

struct MasterWatch::State {
  double period_seconds;
  double silence_seconds;
  mutable std::mutex mutex;
  std::condition_variable stop_changed;
  bool stop = false;
  std::optional<std::string> lost;

  void run(std::optional<int> first_pid) {
    using Clock = std::chrono::steady_clock;
    Clock::time_point last_answer = Clock::now();
    std::unique_lock<std::mutex> lock(mutex);
    while (!stop_changed.wait_for(lock, std::chrono::duration<double>(period_seconds),
                                  [this] { return stop; })) {
      lock.unlock();
      const std::optional<int> pid = masterPid();
      lock.lock();
      if (pid) last_answer = Clock::now();
      const std::string uri = ros::master::getURI();
      if (pid && first_pid && *pid != *first_pid) {
        lost = "the ROS master at " + uri + " restarted (process " + std::to_string(*first_pid) + ", now " +
               std::to_string(*pid) + ")";
      } else if (!pid && Clock::now() - last_answer > std::chrono::duration<double>(silence_seconds)) {
        lost = "the ROS master at " + uri + " has not answered for " +
               std::to_string(static_cast<int>(silence_seconds)) + " s";
      } else {
        first_pid = first_pid ? first_pid : pid;
        continue;
      }
      *lost +=
          ": its registrations of this node are gone, so the simulator exits (with respawn=\"true\" in a "
          "launch file, a fresh one starts and registers with the master)";
      ros::requestShutdown();
      return;
    }
  }
};

MasterWatch::MasterWatch(double period_seconds, double silence_seconds) : state_(std::make_shared<State>()) {
  state_->period_seconds = period_seconds;
  state_->silence_seconds = silence_seconds;
  std::thread([state = state_, pid = masterPid()] { state->run(pid); }).detach();
}

MasterWatch::~MasterWatch() {
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stop = true;
  }
  state_->stop_changed.notify_all();
}

std::optional<std::string> MasterWatch::lost() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->lost;
}

}  // namespace bullet_sim
