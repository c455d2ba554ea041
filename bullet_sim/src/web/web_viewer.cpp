#include "bullet_sim/web/web_viewer.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "viewer_messages.h"
#include "web_server.h"

namespace bullet_sim {

namespace {

constexpr double kRtfWindow = 1.0;   // [wall s] the RTF is measured over about this long
constexpr double kRtfMinSpan = 0.2;  // [wall s] and no shorter

std::string readFile(const std::filesystem::path& path, const std::string& what) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error(what + " is missing: cannot read [" + path.string() + "]");
  std::ostringstream content;
  content << file.rdbuf();
  return content.str();
}

/// The page's files, and the two of three.js it imports, by the paths the page asks them by.
std::map<std::string, ServedFile> pageFiles(const WebViewerOptions& options) {
  namespace fs = std::filesystem;
  const fs::path page(options.page_dir);
  const fs::path three(options.three_dir);
  const std::string html = "text/html; charset=utf-8";
  const std::string script = "text/javascript; charset=utf-8";
  const std::string page_what = "the viewer's page (bullet_sim/web)";
  const std::string three_what = "three.js (Debian's libjs-three: scripts/workspace.sh install)";
  std::map<std::string, ServedFile> files;
  files["/"] = {html, readFile(page / "index.html", page_what)};
  files["/index.html"] = files["/"];
  files["/viewer.js"] = {script, readFile(page / "viewer.js", page_what)};
  files["/viewer.css"] = {"text/css; charset=utf-8", readFile(page / "viewer.css", page_what)};
  for (const char* module : {"build/three.module.js", "examples/jsm/controls/OrbitControls.js"}) {
    files[std::string("/three/") + module] = {script, readFile(three / module, three_what)};
  }
  return files;
}

double seconds(RtfMeter::Clock::duration duration) { return std::chrono::duration<double>(duration).count(); }

}  // namespace

double RtfMeter::add(Clock::time_point wall, double sim_time) {
  if (!samples_.empty() && sim_time < samples_.back().second) {
    samples_.clear();
    factor_ = 0;
  }
  samples_.emplace_back(wall, sim_time);
  // Keep the newest sample that is at least kRtfWindow old, and those after it.
  while (samples_.size() > 2 && seconds(wall - samples_[1].first) >= kRtfWindow) samples_.pop_front();
  const double span = seconds(wall - samples_.front().first);
  if (span >= kRtfMinSpan) factor_ = (sim_time - samples_.front().second) / span;
  return factor_;
}

WebViewer::WebViewer(const WebViewerOptions& options, CommandSink commands) : options_(options) {
  if (!(options_.frame_rate > 0)) throw std::runtime_error("the viewer's frame rate must be > 0 Hz");
  server_ = std::make_unique<WebServer>(options_, pageFiles(options_), std::move(commands));
}

WebViewer::~WebViewer() = default;

uint16_t WebViewer::port() const { return server_->port(); }

size_t WebViewer::viewers() const { return server_->viewers(); }

void WebViewer::update(const Simulation& simulation, bool paused) {
  if (!watched_.empty()) keepCamerasWanted(simulation);
  if (!server_->takeFrameRequest()) return;
  if (layout_stale_ || !layout_) publishLayout(simulation);
  publishFrame(simulation, paused, RtfMeter::Clock::now());
  publishImages(simulation);
}

void WebViewer::publishLayout(const Simulation& simulation) {
  layout_ = std::make_shared<const ViewerLayout>(
      viewerLayout(simulation, ++revision_, options_.max_mesh_triangles));
  layout_stale_ = false;
  server_->publishScene(sceneMessage(layout_));
}

void WebViewer::publishFrame(const Simulation& simulation, bool paused, RtfMeter::Clock::time_point now) {
  ViewerFrame frame = viewerFrame(simulation, *layout_, options_.max_hits);
  frame.paused = paused;
  frame.rtf = rtf_.add(now, simulation.time());
  server_->publishFrame(frameMessage(std::move(frame)));
}

void WebViewer::publishImages(const Simulation& simulation) {
  watched_ = server_->watchedCameras();
  for (const std::string& key : watched_) {
    for (const ViewerCamera& camera : layout_->cameras) {
      if (camera.key != key) continue;
      const Stream<CameraImage>* stream = cameraStream(simulation, camera);
      if (!stream || stream->count() == 0 || image_counts_[key] == stream->count()) continue;
      image_counts_[key] = stream->count();
      server_->publishImage(key, imageOutgoing(key, stream->latest()));
    }
  }
}

void WebViewer::keepCamerasWanted(const Simulation& simulation) {
  if (server_->viewers() == 0) watched_.clear();  // the last page went: no frame comes to say so
  if (!layout_) return;
  for (const std::string& key : watched_) {
    for (const ViewerCamera& camera : layout_->cameras) {
      if (camera.key == key) wantCamera(simulation, camera);
    }
  }
}

}  // namespace bullet_sim
