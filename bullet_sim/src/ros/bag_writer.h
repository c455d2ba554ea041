// Writes messages into one rosbag on a thread of its own, in the order they are given, as `rosbag record`
// lays a bag out: the file is FILE.bag.active until it is closed and renamed FILE.bag. Nothing is dropped:
// when the writer falls behind by more than a bound, the caller waits. A bag that cannot be opened or written
// (a full disk) is reported once, naming the path, and everything after is ignored.
#pragma once

#include <rosbag/bag.h>
#include <topic_tools/shape_shifter.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bullet_sim/tools/run_recorder.h"

namespace bullet_sim {

/// A connection's header for rosbag: latched topics carry latching=1, as `rosbag record` writes them.
using ConnectionHeader = boost::shared_ptr<ros::M_string>;

/// The bag time of sim time `sim_time` [s]: a bag holds no time before ros::TIME_MIN (1 ns).
ros::Time bagTime(double sim_time);

class BagWriter {
 public:
  struct Options {
    rosbag::CompressionType compression = rosbag::compression::LZ4;
    uint32_t chunk_size = 768 * 1024;          ///< [bytes] before compression
    size_t max_queued_bytes = size_t{256} << 20;  ///< the caller waits beyond this
  };

  /// Opens `path`.active (`path` ends in .bag); a failure goes to `errors`, and nothing is recorded.
  BagWriter(std::string path, Options options, RecorderErrors errors);
  /// Closes the bag (close()).
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// False once the bag could not be opened or written.
  bool recording() const { return !failed_; }
  const std::string& path() const { return path_; }

  /// Queues `message` for `topic` at bag time `sim_time` [s]. A `header` makes its own connection (the first
  /// message of a topic decides; later ones must give the same). Messages go to the writer thread in batches.
  template <class Message>
  void write(const std::string& topic, double sim_time, Message message, ConnectionHeader header = nullptr) {
    if (failed_) return;
    pending_.push_back(std::make_unique<MessageJob<Message>>(topic, bagTime(sim_time), std::move(message),
                                                             std::move(header)));
    pending_bytes_ += pending_.back()->bytes;
    if (pending_.size() >= kBatch) flush();
  }
  /// Hands the messages written since the last batch to the writer thread.
  void flush();

  /// Writes what is queued, closes the bag and renames it from FILE.bag.active to FILE.bag; false when
  /// recording stopped on an error (the .active file then stays, for `rosbag reindex`).
  bool close();

 private:
  struct Job {
    virtual ~Job() = default;
    virtual void write(rosbag::Bag& bag) const = 0;
    size_t bytes = 0;  ///< what it holds in memory, about
  };
  template <class Message>
  struct MessageJob final : Job {
    MessageJob(std::string topic, ros::Time time, Message message, ConnectionHeader header)
        : topic(std::move(topic)), time(time), message(std::move(message)), header(std::move(header)) {
      bytes = this->topic.size() + serializedLength(this->message);
    }
    void write(rosbag::Bag& bag) const override { bag.write(topic, time, message, header); }
    std::string topic;
    ros::Time time;
    Message message;
    ConnectionHeader header;
  };
  template <class Message>
  static size_t serializedLength(const Message& message) {
    return ros::serialization::serializationLength(message);
  }
  static size_t serializedLength(const topic_tools::ShapeShifter::ConstPtr& message) {
    return message->size();
  }

  /// Messages handed to the writer thread at once: one lock and one wake-up for many (at RTF 1, a batch of
  /// the wheelchair's topics is 0.2 s of sim time).
  static constexpr size_t kBatch = 64;

  /// The writer thread: writes the jobs in order until closed.
  void run();
  /// Reports `what` about the file, once, and stops recording.
  void fail(const std::string& what);

  const std::string path_;
  const std::string active_path_;
  const Options options_;
  const RecorderErrors errors_;
  /// rosbag's destructor closes the file and throws (std::terminate) when it cannot write: a bag whose writes
  /// failed is let go unclosed, its file still open.
  std::unique_ptr<rosbag::Bag> bag_;
  std::atomic<bool> failed_{false};
  std::mutex mutex_;
  std::condition_variable work_;   ///< a job came, or closing
  std::condition_variable space_;  ///< the queue shrank
  std::deque<std::unique_ptr<Job>> queue_;
  size_t queued_bytes_ = 0;
  bool writer_waiting_ = false;
  std::vector<std::unique_ptr<Job>> pending_;  ///< the caller's, not yet queued
  size_t pending_bytes_ = 0;
  bool closing_ = false;
  bool closed_ = false;
  std::thread thread_;
};

}  // namespace bullet_sim
