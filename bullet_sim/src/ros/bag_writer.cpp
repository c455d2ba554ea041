#include "bag_writer.h"

#include <pthread.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace bullet_sim {

ros::Time bagTime(double sim_time) { return std::max(ros::TIME_MIN, ros::Time(std::max(0.0, sim_time))); }

BagWriter::BagWriter(std::string path, Options options, RecorderErrors errors)
    : path_(std::move(path)), active_path_(path_ + ".active"), options_(options), errors_(std::move(errors)),
      bag_(std::make_unique<rosbag::Bag>()) {
  errno = 0;
  try {
    bag_->setCompression(options_.compression);
    bag_->setChunkThreshold(options_.chunk_size);
    bag_->open(active_path_, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    fail(e.what());
    return;
  }
  thread_ = std::thread([this] { run(); });
  pthread_setname_np(thread_.native_handle(), "bag_writer");  // for top and bench_record.py
}

BagWriter::~BagWriter() { close(); }

void BagWriter::flush() {
  if (pending_.empty()) return;
  std::unique_lock<std::mutex> lock(mutex_);
  space_.wait(lock, [&] {
    return failed_ || queued_bytes_ == 0 || queued_bytes_ + pending_bytes_ <= options_.max_queued_bytes;
  });
  if (!failed_) {
    queued_bytes_ += pending_bytes_;
    for (auto& job : pending_) queue_.push_back(std::move(job));
    if (writer_waiting_) work_.notify_one();
  }
  pending_.clear();
  pending_bytes_ = 0;
}

void BagWriter::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    writer_waiting_ = true;
    work_.wait(lock, [&] { return closing_ || !queue_.empty(); });
    writer_waiting_ = false;
    if (queue_.empty()) return;  // closing, and all written
    std::deque<std::unique_ptr<Job>> jobs;
    jobs.swap(queue_);
    lock.unlock();
    size_t bytes = 0;
    for (const auto& job : jobs) {
      bytes += job->bytes;
      if (failed_) continue;
      errno = 0;
      try {
        job->write(*bag_);
      } catch (const rosbag::BagException& e) {
        fail(e.what());
      }
    }
    jobs.clear();
    lock.lock();
    queued_bytes_ -= bytes;
    space_.notify_all();
  }
}

void BagWriter::fail(const std::string& what) {
  const int error = errno;  // what made stdio fail, which rosbag's message leaves out
  if (failed_.exchange(true)) return;
  std::string why = what;
  if (error != 0) why += " (" + std::string(std::strerror(error)) + ")";
  errors_("cannot write the bag [" + active_path_ + "]: " + why + "; recording stopped");
  { std::lock_guard<std::mutex> lock(mutex_); }  // a caller waiting for space sees failed_
  space_.notify_all();
}

bool BagWriter::close() {
  if (closed_) return !failed_;
  closed_ = true;
  flush();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  work_.notify_one();
  if (thread_.joinable()) thread_.join();
  if (failed_) {
    if (bag_->isOpen()) static_cast<void>(bag_.release());  // see bag_
    return false;
  }
  errno = 0;
  try {
    bag_->close();
  } catch (const rosbag::BagException& e) {
    fail(e.what());
    static_cast<void>(bag_.release());
    return false;
  }
  if (std::rename(active_path_.c_str(), path_.c_str()) != 0) {
    errors_("cannot rename the bag [" + active_path_ + "] to [" + path_ + "]: " + std::strerror(errno));
    failed_ = true;
    return false;
  }
  return true;
}

}  // namespace bullet_sim
