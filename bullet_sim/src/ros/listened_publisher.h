// A publisher that knows whether anyone listens without asking roscpp. roscpp's publish() and
// getNumSubscribers() take the lock its network thread holds while it writes to subscribers' sockets; with
// ten robots driving, a fifth of the node thread's switches were waits on that lock, mostly to publish topics
// nobody subscribed to. Here roscpp's connect and disconnect callbacks keep the count, and a message nobody
// would receive is neither built nor handed to roscpp.
#pragma once

#include <ros/ros.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace bullet_sim {

class ListenedPublisher {
 public:
  ListenedPublisher() = default;

  /// Advertises `topic` (not latched) on `handle`; empty, as roscpp's, when roscpp refuses it.
  template <class Message>
  static ListenedPublisher advertise(ros::NodeHandle& handle, const std::string& topic, uint32_t queue_size) {
    ListenedPublisher advertised;
    auto listeners = advertised.listeners_;
    // The callbacks run on the handle's queue (the node's thread, between steps); a later subscriber is heard
    // from the next step on, as roscpp connects it.
    advertised.publisher_ = handle.advertise<Message>(
        topic, queue_size, [listeners](const ros::SingleSubscriberPublisher&) { ++*listeners; },
        [listeners](const ros::SingleSubscriberPublisher&) { --*listeners; });
    return advertised;
  }

  explicit operator bool() const { return static_cast<bool>(publisher_); }
  const ros::Publisher& publisher() const { return publisher_; }
  uint32_t listeners() const { return static_cast<uint32_t>(std::max(listeners_->load(), 0)); }
  bool heard() const { return listeners_->load() > 0; }

  /// Publishes what `build` makes, built only when someone listens.
  template <class Build>
  void publishBuilt(Build build) const {
    if (heard()) publisher_.publish(build());
  }

 private:
  ros::Publisher publisher_;
  std::shared_ptr<std::atomic<int>> listeners_ = std::make_shared<std::atomic<int>>(0);
};

}  // namespace bullet_sim
