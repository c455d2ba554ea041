// bench --web-viewer's page: a client of the live viewer's WebSocket that takes in every message and
// acknowledges frames and images as the browser page does, on a thread of its own.
#pragma once

#include <cstdint>
#include <memory>

namespace bullet_sim {

class ViewerProbe {
 public:
  /// Opens the viewer's socket on 127.0.0.1:`port` as its own page. Throws std::runtime_error when it cannot.
  explicit ViewerProbe(uint16_t port);
  ~ViewerProbe();

  /// Frames (and camera images) taken in so far.
  uint64_t frames() const;
  /// Waits until it has taken in `count` frames, at most `seconds` [s]; false if it has not.
  bool waitForFrames(uint64_t count, double seconds) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bullet_sim
