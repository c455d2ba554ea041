// Watch a running simulation in a browser: a page (bullet_sim/web, drawn by three.js) that shows the world,
// every robot's links, lidar hits, a chosen camera's latest image, sim time and RTF, live, and sends pause,
// resume, reset and teleop back. ROS-free: the host (the simulator node, bench) calls update() after every
// step and applies the commands between steps.
//
// Costs the simulation one atomic load per update, and, when a page is ready for a frame (at most frame_rate
// times per wall second), a snapshot of the poses and hits; the server's thread turns it into JSON. A slow or
// vanished page gets fewer frames: the simulation never waits for it.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

struct WebViewerOptions {
  std::string address = "127.0.0.1";  ///< the address it listens on; "0.0.0.0" for every interface
  uint16_t port = 0;                  ///< 0: a free port (see WebViewer::port)
  /// Origins besides its own whose pages may connect ("http://myhost:8080"): a page of another origin cannot.
  std::vector<std::string> allowed_origins;
  /// Whether pages connected from beyond this machine may pause, reset and drive; from it they always may.
  bool control_beyond_localhost = false;
  std::string page_dir;  ///< holds index.html, viewer.js, viewer.css (bullet_sim/web)
  std::string three_dir = "/usr/share/javascript/three";  ///< Debian's libjs-three
  double frame_rate = 30;           ///< [wall Hz] at most, per page
  size_t max_viewers = 8;           ///< more pages at once are refused
  size_t max_mesh_triangles = 20000;  ///< a mesh with more is simplified to about this many for the page
  size_t max_hits = 20000;          ///< lidar hits per frame; more are thinned evenly
};

/// What a page asks of the simulation; the host applies it between steps.
struct ViewerCommand {
  enum class Kind { kPause, kResume, kReset, kTeleop };
  Kind kind = Kind::kPause;
  std::string robot;   ///< kTeleop: the robot whose velocity input (cmd_vel) gets the command
  double linear = 0;   ///< [m/s] forward
  double angular = 0;  ///< [rad/s] counter-clockwise
};

class WebServer;
struct ViewerLayout;

/// The sim time [s] covered per wall second, over the last second or so of wall time.
class RtfMeter {
 public:
  using Clock = std::chrono::steady_clock;
  /// Adds a sample; a sim time below the last one (a reset) starts over. Returns the factor, 0 until known.
  double add(Clock::time_point wall, double sim_time);

 private:
  std::deque<std::pair<Clock::time_point, double>> samples_;
  double factor_ = 0;
};

class WebViewer {
 public:
  using CommandSink = std::function<void(const ViewerCommand& command)>;

  /// Starts serving. `commands` is called on the server's thread: queue what it gets for between steps.
  /// Throws std::runtime_error saying what is wrong: the page's or three.js's files missing, the address
  /// not one, the port taken.
  WebViewer(const WebViewerOptions& options, CommandSink commands);
  ~WebViewer();

  uint16_t port() const;
  /// Pages connected now.
  size_t viewers() const;

  /// After every step, and while paused (`paused`): publishes a frame when a page is ready for one.
  /// Keeps the cameras that pages watch rendering, as a subscriber does.
  void update(const Simulation& simulation, bool paused);
  /// A robot or a world model came or went: pages are sent the geometry again.
  void modelsChanged() { layout_stale_ = true; }

 private:
  void publishLayout(const Simulation& simulation);
  void publishFrame(const Simulation& simulation, bool paused, RtfMeter::Clock::time_point now);
  void publishImages(const Simulation& simulation);
  void keepCamerasWanted(const Simulation& simulation);

  WebViewerOptions options_;
  std::unique_ptr<WebServer> server_;
  std::shared_ptr<const ViewerLayout> layout_;
  bool layout_stale_ = true;
  uint64_t revision_ = 0;
  RtfMeter rtf_;
  std::vector<std::string> watched_;                   ///< cameras some page watches, as of the last frame
  std::map<std::string, uint64_t> image_counts_;  ///< per camera, the count of the image published last
};

}  // namespace bullet_sim
