// The live viewer's server (Boost.Beast): serves the page's files over HTTP and, over a WebSocket at /ws,
// pushes each page the latest messages the simulation published, one at a time: a page that reads slowly gets
// fewer frames, never a queue, and the simulation never waits for it. The server asks the simulation for a
// frame when a page is ready for one, at most frame_rate times a second (takeFrameRequest: one atomic load
// per step otherwise). What pages ask (pause, teleop, ...) goes to a CommandSink, on the server's thread: the
// host queues it for between steps. ROS-free.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/web/web_viewer.h"

namespace bullet_sim {

/// A message for the pages, built on one thread (the simulation's) and turned into bytes once, on the
/// server's thread, and only when a page is sent it.
class Outgoing {
 public:
  explicit Outgoing(bool binary) : binary_(binary) {}
  virtual ~Outgoing() = default;
  bool binary() const { return binary_; }
  const std::string& bytes() const;

 protected:
  virtual std::string serialise() const = 0;

 private:
  bool binary_;
  mutable std::once_flag once_;
  mutable std::string bytes_;
};

/// A text message that is bytes already.
class TextMessage final : public Outgoing {
 public:
  explicit TextMessage(std::string text) : Outgoing(false), text_(std::move(text)) {}

 private:
  std::string serialise() const override { return text_; }
  std::string text_;
};

/// A file the server answers a GET with.
struct ServedFile {
  std::string content_type;
  std::string body;
};

/// What a page sent: a command for the simulation, the camera it wants to watch ("" for none), or that it has
/// taken in a frame or an image.
struct ClientMessage {
  std::optional<ViewerCommand> command;
  std::optional<std::string> camera;
  bool ack = false;
  std::string error;  ///< why the message was refused; empty when one of the above is set
};

/// Reads a page's JSON message: {"type": "pause" | "resume" | "reset" | "ack"}, {"type": "teleop", "robot":
/// NAME, "linear": [m/s], "angular": [rad/s]} (finite numbers) or {"type": "camera", "name": NAME}.
ClientMessage parseClientMessage(const std::string& text);

/// Whether a WebSocket upgrade whose Origin header is `origin`, sent to `host` (its Host header), may open:
/// `origin` is listed in `allowed`, or it is the page's own origin, "http://" + host, where host names the
/// server by an IP address or as localhost (a DNS name could be another site's, rebound to this address).
bool originAllowed(const std::string& origin, const std::string& host,
                   const std::vector<std::string>& allowed);

/// Whether a page connected from `remote_address` may pause, reset and drive: from this machine (loopback,
/// which an SSH tunnel's connections come from) always; from elsewhere only with `control_beyond_localhost`.
bool mayControl(const std::string& remote_address, bool control_beyond_localhost);

class WebServer {
 public:
  using CommandSink = std::function<void(const ViewerCommand& command)>;

  /// Listens on options.address:options.port (0: a free port) and serves `files` by their paths ("/",
  /// "/viewer.js"). Throws std::runtime_error naming the address and the reason when it cannot listen.
  WebServer(const WebViewerOptions& options, std::map<std::string, ServedFile> files, CommandSink commands);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  uint16_t port() const;
  /// Pages connected now; safe from any thread.
  size_t viewers() const;
  /// Whether a page is ready for a frame (then the next call says false until one is again); any thread.
  bool takeFrameRequest();

  // From any thread: the latest of each kind is what pages are sent next.
  void publishScene(std::shared_ptr<const Outgoing> scene);
  void publishFrame(std::shared_ptr<const Outgoing> frame);
  void publishImage(const std::string& camera, std::shared_ptr<const Outgoing> image);
  /// The cameras some page watches, each once.
  std::vector<std::string> watchedCameras() const;

  struct Impl;  // web_server.cpp

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace bullet_sim
