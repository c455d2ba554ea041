#include "web_server.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <deque>
#include <set>
#include <stdexcept>
#include <thread>

namespace bullet_sim {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

namespace {

constexpr std::chrono::seconds kHttpTimeout{30};
/// A page that neither sends nor answers the pings for this long is gone: its session ends.
constexpr std::chrono::seconds kViewerIdleTimeout{20};
constexpr size_t kMaxRequestBody = 1024;   // [bytes] the page only GETs
constexpr size_t kMaxClientMessage = 4096;  // [bytes]
constexpr size_t kMaxPendingReplies = 8;
/// Frames and images sent to a page that it has not acknowledged yet: a page that draws slowly (software
/// WebGL) gets fewer frames instead of a backlog in its socket, so what it shows stays current.
constexpr int kMaxUnacknowledged = 2;
/// The page loads only its own files and talks only to its own server, and no other site may frame it.
constexpr const char* kContentSecurityPolicy =
    "default-src 'self'; connect-src 'self'; img-src 'self' data: blob:; frame-ancestors 'none'";

std::string withoutPort(const std::string& host) {
  if (!host.empty() && host.front() == '[') return host.substr(0, host.find(']') + 1);  // [::1]:8080
  const auto colon = host.find(':');
  return colon == std::string::npos ? host : host.substr(0, colon);
}

bool isIpAddressOrLocalhost(const std::string& name) {
  if (name == "localhost") return true;
  std::string literal = name;
  if (literal.size() > 2 && literal.front() == '[' && literal.back() == ']')
    literal = literal.substr(1, literal.size() - 2);
  beast::error_code ec;
  net::ip::make_address(literal, ec);
  return !ec;
}

std::string errorJson(const std::string& message) {
  return nlohmann::json{{"type", "error"}, {"message", message}}.dump();
}

}  // namespace

const std::string& Outgoing::bytes() const {
  std::call_once(once_, [this] { bytes_ = serialise(); });
  return bytes_;
}

ClientMessage parseClientMessage(const std::string& text) {
  ClientMessage message;
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object() || !json.contains("type") || !json["type"].is_string()) {
    message.error = "a message must be a JSON object with a \"type\"";
    return message;
  }
  const std::string type = json["type"];
  const std::map<std::string, ViewerCommand::Kind> plain = {
      {"pause", ViewerCommand::Kind::kPause}, {"resume", ViewerCommand::Kind::kResume},
      {"reset", ViewerCommand::Kind::kReset}};
  if (const auto kind = plain.find(type); kind != plain.end()) {
    message.command = ViewerCommand{kind->second};
  } else if (type == "ack") {
    message.ack = true;
  } else if (type == "camera") {
    if (json.contains("name") && json["name"].is_string()) message.camera = json["name"].get<std::string>();
    else message.error = "a camera message needs a \"name\" string (\"\" for none)";
  } else if (type == "teleop") {
    const auto number = [&](const char* key) {
      return json.contains(key) && json[key].is_number() ? json[key].get<double>() : NAN;
    };
    ViewerCommand command{ViewerCommand::Kind::kTeleop, "", number("linear"), number("angular")};
    if (!json.contains("robot") || !json["robot"].is_string() || !std::isfinite(command.linear) ||
        !std::isfinite(command.angular)) {
      message.error =
          "a teleop message needs \"robot\" (a string), \"linear\" and \"angular\" (finite numbers)";
    } else {
      command.robot = json["robot"];
      message.command = command;
    }
  } else {
    message.error = "unknown message type [" + type + "]: use pause, resume, reset, teleop, camera or ack";
  }
  return message;
}

bool originAllowed(const std::string& origin, const std::string& host,
                   const std::vector<std::string>& allowed) {
  if (origin.empty()) return false;
  for (const auto& listed : allowed) {
    if (origin == listed) return true;
  }
  return !host.empty() && origin == "http://" + host && isIpAddressOrLocalhost(withoutPort(host));
}

bool mayControl(const std::string& remote_address, bool control_beyond_localhost) {
  if (control_beyond_localhost) return true;
  beast::error_code ec;
  const net::ip::address address = net::ip::make_address(remote_address, ec);
  if (ec) return false;
  if (address.is_v6() && address.to_v6().is_v4_mapped()) {
    return net::ip::make_address_v4(net::ip::v4_mapped, address.to_v6()).is_loopback();
  }
  return address.is_loopback();
}

struct WebServer::Impl {
  struct Slot {
    uint64_t sequence = 0;
    std::shared_ptr<const Outgoing> message;
  };
  class ViewerSession;
  class HttpSession;

  Impl(const WebViewerOptions& options, std::map<std::string, ServedFile> files, CommandSink commands)
      : options(options), files(std::move(files)), commands(std::move(commands)) {}

  void listen();
  void accept();
  void schedulePump();
  void pumpViewers();
  /// A page is ready for a frame: asks the simulation for one, at most frame_rate times a second.
  void wantFrame();
  Response respond(const Request& request) const;
  /// The answer refusing a WebSocket upgrade, or nullopt when it may open.
  std::optional<Response> refuseUpgrade(const Request& request) const;
  void watch(const std::string& before, const std::string& after);

  // What sessions use, declared before the io_context, whose destruction ends them.
  const WebViewerOptions options;
  const std::map<std::string, ServedFile> files;
  const CommandSink commands;
  uint16_t port = 0;  ///< the one it listens on
  std::atomic<size_t> viewers{0};
  std::atomic<bool> pump_posted{false};
  std::atomic<bool> stopping{false};
  std::atomic<bool> frame_wanted{false};  ///< the simulation publishes a frame at its next update
  mutable std::mutex mutex;  ///< guards the slots and `watched`
  Slot scene, frame;
  std::map<std::string, Slot> images;
  std::multiset<std::string> watched;
  std::vector<std::weak_ptr<ViewerSession>> sessions;  ///< on the io thread only

  net::io_context io{1};
  tcp::acceptor acceptor{io};
  net::steady_timer request_timer{io};
  bool request_armed = false;                          ///< on the io thread
  std::chrono::steady_clock::time_point last_request;  ///< on the io thread
  std::thread thread;
};

/// One page's WebSocket: sends it the latest scene, frame and image, one message at a time, and hands what it
/// sends to the command sink.
class WebServer::Impl::ViewerSession : public std::enable_shared_from_this<ViewerSession> {
 public:
  ViewerSession(beast::tcp_stream stream, Impl& server, bool may_control)
      : ws_(std::move(stream)), server_(server), may_control_(may_control) {
    ++server_.viewers;
  }
  ~ViewerSession() {
    server_.watch(camera_, "");
    --server_.viewers;
  }

  void accept(Request request) {
    request_ = std::move(request);
    beast::get_lowest_layer(ws_).expires_never();  // the WebSocket's own timeouts take over
    websocket::stream_base::timeout timeouts =
        websocket::stream_base::timeout::suggested(beast::role_type::server);
    timeouts.idle_timeout = kViewerIdleTimeout;
    ws_.set_option(timeouts);
    ws_.read_message_max(kMaxClientMessage);
    ws_.async_accept(request_, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->server_.sessions.push_back(self);
      self->replies_.push_back(std::make_shared<TextMessage>(
          nlohmann::json{{"type", "hello"}, {"control", self->may_control_}}.dump()));
      self->read();
      self->pump();
    });
  }

  /// Sends the next message due, unless one is on its way.
  void pump() {
    if (writing_ || server_.stopping) return;
    const std::shared_ptr<const Outgoing> message = next();
    if (!message && unacknowledged_ < kMaxUnacknowledged) server_.wantFrame();
    if (!message) return;
    writing_ = true;
    ws_.binary(message->binary());
    ws_.async_write(net::buffer(message->bytes()),
                    [self = shared_from_this(), message](beast::error_code ec, size_t) {
                      self->writing_ = false;
                      if (!ec) self->pump();
                    });
  }

 private:
  /// Replies first, then a scene the page has not seen, then frames and images in turn.
  std::shared_ptr<const Outgoing> next() {
    if (!replies_.empty()) {
      auto reply = replies_.front();
      replies_.pop_front();
      return reply;
    }
    const std::lock_guard<std::mutex> lock(server_.mutex);
    if (server_.scene.message && server_.scene.sequence != scene_seen_) {
      scene_seen_ = server_.scene.sequence;
      return server_.scene.message;
    }
    if (scene_seen_ == 0 || unacknowledged_ >= kMaxUnacknowledged)
      return nullptr;  // frames name the scene's bodies
    const auto image = camera_.empty() ? server_.images.end() : server_.images.find(camera_);
    const bool image_due = image != server_.images.end() && image->second.sequence != image_seen_;
    const bool frame_due = server_.frame.message && server_.frame.sequence != frame_seen_;
    if (frame_due && !(image_due && last_was_frame_)) {
      frame_seen_ = server_.frame.sequence;
      last_was_frame_ = true;
      ++unacknowledged_;
      return server_.frame.message;
    }
    if (!image_due) return nullptr;
    image_seen_ = image->second.sequence;
    last_was_frame_ = false;
    ++unacknowledged_;
    return image->second.message;
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) return self->ended();
      self->handle(beast::buffers_to_string(self->buffer_.data()));
      self->buffer_.consume(self->buffer_.size());
      self->read();
    });
  }

  void handle(const std::string& text) {
    const ClientMessage message = parseClientMessage(text);
    if (message.ack) {
      unacknowledged_ = std::max(0, unacknowledged_ - 1);
    } else if (message.camera) {
      server_.watch(camera_, *message.camera);
      camera_ = *message.camera;
      image_seen_ = 0;
    } else if (message.command && !may_control_) {
      reply(errorJson("this page is read-only: it connected from beyond the simulator's machine (start the "
                      "simulator with _web_control:=true to let such pages pause, reset and drive)"));
    } else if (message.command) {
      if (message.command->kind == ViewerCommand::Kind::kTeleop) drove(*message.command);
      server_.commands(*message.command);
    } else {
      reply(errorJson(message.error));
    }
    pump();
  }

  /// Remembers the robot a teleop command sets moving, and stops the one it drove before.
  void drove(const ViewerCommand& command) {
    if (!driven_.empty() && driven_ != command.robot) {
      server_.commands(ViewerCommand{ViewerCommand::Kind::kTeleop, driven_});
    }
    driven_ = command.linear != 0 || command.angular != 0 ? command.robot : "";
  }

  /// The page went: the robot it was driving stops.
  void ended() {
    if (!driven_.empty() && !server_.stopping) {
      server_.commands(ViewerCommand{ViewerCommand::Kind::kTeleop, driven_});
    }
  }

  void reply(const std::string& text) {
    if (replies_.size() < kMaxPendingReplies) replies_.push_back(std::make_shared<TextMessage>(text));
  }

  websocket::stream<beast::tcp_stream> ws_;
  Impl& server_;
  const bool may_control_;
  Request request_;
  beast::flat_buffer buffer_;
  bool writing_ = false;
  bool last_was_frame_ = false;
  int unacknowledged_ = 0;  ///< frames and images sent and not acknowledged
  std::deque<std::shared_ptr<const Outgoing>> replies_;
  uint64_t scene_seen_ = 0, frame_seen_ = 0, image_seen_ = 0;
  std::string camera_;
  std::string driven_;  ///< the robot this page set moving, "" when none
};

/// One HTTP connection: answers GETs of the page's files, and hands a WebSocket upgrade to a ViewerSession.
class WebServer::Impl::HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Impl& server) : stream_(std::move(socket)), server_(server) {}

  void read() {
    parser_.emplace();
    parser_->body_limit(kMaxRequestBody);
    stream_.expires_after(kHttpTimeout);
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) return self->close();
      Request request = self->parser_->release();
      if (websocket::is_upgrade(request)) return self->upgrade(std::move(request));
      self->write(self->server_.respond(request));
    });
  }

 private:
  void upgrade(Request request) {
    if (auto refusal = server_.refuseUpgrade(request)) return write(std::move(*refusal));
    beast::error_code ec;
    const std::string remote = stream_.socket().remote_endpoint(ec).address().to_string();
    const bool control = !ec && mayControl(remote, server_.options.control_beyond_localhost);
    std::make_shared<ViewerSession>(std::move(stream_), server_, control)->accept(std::move(request));
  }

  void write(Response response) {
    auto shared = std::make_shared<Response>(std::move(response));
    http::async_write(stream_, *shared, [self = shared_from_this(), shared](beast::error_code ec, size_t) {
      if (ec || !shared->keep_alive()) return self->close();
      self->read();
    });
  }

  void close() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
  }

  beast::tcp_stream stream_;
  Impl& server_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

void WebServer::Impl::listen() {
  beast::error_code ec;
  const net::ip::address address = net::ip::make_address(options.address, ec);
  if (ec)
    throw std::runtime_error("[" + options.address + "] is not an IP address (e.g. 127.0.0.1 or 0.0.0.0)");
  const tcp::endpoint endpoint(address, options.port);
  const std::string where = options.address + ":" + std::to_string(options.port);
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (ec == net::error::address_in_use) {
    throw std::runtime_error("cannot listen on " + where + ": another program already listens there");
  }
  if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (!ec) port = acceptor.local_endpoint(ec).port();
  if (ec) throw std::runtime_error("cannot listen on " + where + ": " + ec.message());
}

void WebServer::Impl::accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!ec) std::make_shared<HttpSession>(std::move(socket), *this)->read();
    if (acceptor.is_open()) accept();
  });
}

void WebServer::Impl::schedulePump() {
  if (pump_posted.exchange(true)) return;
  net::post(io, [this] {
    pump_posted = false;
    pumpViewers();
  });
}

void WebServer::Impl::wantFrame() {
  if (request_armed || frame_wanted.load(std::memory_order_relaxed)) return;
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1 / options.frame_rate));
  const auto ask = [this] {
    last_request = std::chrono::steady_clock::now();
    frame_wanted.store(true, std::memory_order_release);
  };
  if (std::chrono::steady_clock::now() >= last_request + period) return ask();
  request_armed = true;
  request_timer.expires_at(last_request + period);
  request_timer.async_wait([this, ask](beast::error_code ec) {
    request_armed = false;
    if (!ec) ask();
  });
}

void WebServer::Impl::pumpViewers() {
  std::vector<std::weak_ptr<ViewerSession>> alive;
  for (const auto& weak : sessions) {
    if (auto session = weak.lock()) {
      session->pump();
      alive.push_back(weak);
    }
  }
  sessions = std::move(alive);
}

Response WebServer::Impl::respond(const Request& request) const {
  const std::string target(request.target().substr(0, request.target().find('?')));
  const auto file = files.find(target);
  Response response;
  response.version(request.version());
  response.keep_alive(request.keep_alive());
  response.set(http::field::server, "bullet_sim");
  if (request.method() != http::verb::get) {
    response.result(http::status::method_not_allowed);
    response.set(http::field::allow, "GET");
  } else if (file == files.end()) {
    response.result(http::status::not_found);
    response.set(http::field::content_type, "text/plain");
    response.body() = "no such page: " + target + "\n";
  } else {
    response.result(http::status::ok);
    response.set(http::field::content_type, file->second.content_type);
    response.set(http::field::cache_control, "no-cache");
    response.set("X-Content-Type-Options", "nosniff");
    response.set("X-Frame-Options", "DENY");
    response.set("Content-Security-Policy", kContentSecurityPolicy);
    response.body() = file->second.body;
  }
  response.prepare_payload();
  return response;
}

std::optional<Response> WebServer::Impl::refuseUpgrade(const Request& request) const {
  const auto refusal = [&](http::status status, const std::string& why) {
    Response response{status, request.version()};
    response.set(http::field::content_type, "text/plain");
    response.keep_alive(false);
    response.body() = why + "\n";
    response.prepare_payload();
    return response;
  };
  if (request.target() != "/ws") return refusal(http::status::not_found, "the viewer's WebSocket is /ws");
  const std::string origin(request[http::field::origin]);
  if (!originAllowed(origin, std::string(request[http::field::host]), options.allowed_origins)) {
    return refusal(http::status::forbidden,
                   "origin [" + origin + "] may not open this viewer: only its own page may, and the origins "
                   "listed in ~web_allowed_origins");
  }
  if (viewers >= options.max_viewers) {
    return refusal(
        http::status::service_unavailable,
        std::to_string(options.max_viewers) + " pages are open already, the most this viewer serves");
  }
  return std::nullopt;
}

void WebServer::Impl::watch(const std::string& before, const std::string& after) {
  const std::lock_guard<std::mutex> lock(mutex);
  if (!before.empty()) {
    if (const auto it = watched.find(before); it != watched.end()) watched.erase(it);
  }
  if (!after.empty()) watched.insert(after);
}

WebServer::WebServer(const WebViewerOptions& options, std::map<std::string, ServedFile> files,
                     CommandSink commands)
    : impl_(std::make_unique<Impl>(options, std::move(files), std::move(commands))) {
  impl_->listen();
  impl_->accept();
  impl_->thread = std::thread([io = &impl_->io] { io->run(); });
}

WebServer::~WebServer() {
  impl_->stopping = true;
  impl_->io.stop();
  impl_->thread.join();
}

uint16_t WebServer::port() const { return impl_->port; }

size_t WebServer::viewers() const { return impl_->viewers.load(std::memory_order_relaxed); }

bool WebServer::takeFrameRequest() {
  std::atomic<bool>& wanted = impl_->frame_wanted;
  return wanted.load(std::memory_order_relaxed) && wanted.exchange(false, std::memory_order_acquire);
}

void WebServer::publishScene(std::shared_ptr<const Outgoing> scene) {
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->scene = {impl_->scene.sequence + 1, std::move(scene)};
  }
  impl_->schedulePump();
}

void WebServer::publishFrame(std::shared_ptr<const Outgoing> frame) {
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->frame = {impl_->frame.sequence + 1, std::move(frame)};
  }
  impl_->schedulePump();
}

void WebServer::publishImage(const std::string& camera, std::shared_ptr<const Outgoing> image) {
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    Impl::Slot& slot = impl_->images[camera];
    slot = {slot.sequence + 1, std::move(image)};
  }
  impl_->schedulePump();
}

std::vector<std::string> WebServer::watchedCameras() const {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  std::vector<std::string> names;
  for (const auto& name : impl_->watched) {
    if (names.empty() || names.back() != name) names.push_back(name);
  }
  return names;
}

}  // namespace bullet_sim
