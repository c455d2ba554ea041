#include "bench/bench_viewer.h"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace bullet_sim {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

struct ViewerProbe::Impl {
  net::io_context io;
  websocket::stream<tcp::socket> ws{io};
  beast::flat_buffer buffer;
  mutable std::mutex mutex;  ///< guards `frames` for waitForFrames
  mutable std::condition_variable more;
  uint64_t frames = 0;
  std::thread thread;

  void read() {
    ws.async_read(buffer, [this](beast::error_code ec, size_t) {
      if (ec) return;
      const bool frame =
          ws.got_binary() ||
          beast::buffers_to_string(buffer.data()).find(R"("type":"frame")") != std::string::npos;
      buffer.consume(buffer.size());
      if (frame) {
        {
          const std::lock_guard<std::mutex> lock(mutex);
          ++frames;
        }
        more.notify_all();
        ws.write(net::buffer(std::string(R"({"type":"ack"})")), ec);
        if (ec) return;
      }
      read();
    });
  }
};

ViewerProbe::ViewerProbe(uint16_t port) : impl_(std::make_unique<Impl>()) {
  const std::string host = "127.0.0.1:" + std::to_string(port);
  beast::error_code ec;
  impl_->ws.next_layer().connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port), ec);
  impl_->ws.set_option(websocket::stream_base::decorator([host](websocket::request_type& request) {
    request.set(beast::http::field::origin, "http://" + host);
  }));
  if (!ec) impl_->ws.handshake(host, "/ws", ec);
  if (ec) throw std::runtime_error("cannot open the viewer's socket at " + host + ": " + ec.message());
  impl_->read();
  impl_->thread = std::thread([impl = impl_.get()] { impl->io.run(); });
}

ViewerProbe::~ViewerProbe() {
  impl_->io.stop();
  impl_->thread.join();
}

uint64_t ViewerProbe::frames() const {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->frames;
}

bool ViewerProbe::waitForFrames(uint64_t count, double seconds) const {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  return impl_->more.wait_for(lock, std::chrono::duration<double>(seconds),
                              [&] { return impl_->frames >= count; });
}

}  // namespace bullet_sim
