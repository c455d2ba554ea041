// The live viewer without ROS or a browser: its rules (origins, who may control, page messages), mesh
// simplification, and the server over real sockets, with a Beast client standing in for the page.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "bullet_sim/scene/simulation_images.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/web/web_viewer.h"
#include "src/web/mesh_simplify.h"
#include "src/web/web_server.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using Json = nlohmann::json;
using ::testing::HasSubstr;

constexpr int kReadTimeoutSeconds = 10;  // a page client's read that gets nothing this long fails the test

// ---- rules ----

TEST(WebViewerRules, OnlyItsOwnPageOrAListedOriginMayOpenTheSocket) {
  EXPECT_TRUE(originAllowed("http://localhost:8080", "localhost:8080", {}));
  EXPECT_TRUE(originAllowed("http://127.0.0.1:8080", "127.0.0.1:8080", {}));
  EXPECT_TRUE(originAllowed("http://[::1]:8080", "[::1]:8080", {}));
  EXPECT_TRUE(originAllowed("http://192.168.1.7:8080", "192.168.1.7:8080", {}));
  EXPECT_FALSE(originAllowed("http://evil.example", "localhost:8080", {}));
  EXPECT_FALSE(originAllowed("http://localhost:9999", "localhost:8080", {}));
  EXPECT_FALSE(originAllowed("", "localhost:8080", {}));
  EXPECT_FALSE(originAllowed("null", "localhost:8080", {}));
  // A DNS name could be another site's, rebound to this address: its page must be listed to connect.
  EXPECT_FALSE(originAllowed("http://rebound.example:8080", "rebound.example:8080", {}));
  EXPECT_TRUE(originAllowed("http://robots.lab:8080", "robots.lab:8080", {"http://robots.lab:8080"}));
  EXPECT_TRUE(
      originAllowed("https://dash.lab", "localhost:8080", {"http://robots.lab:8080", "https://dash.lab"}));
}

TEST(WebViewerRules, OnlyPagesOnThisMachineMayControlUnlessAllowed) {
  EXPECT_TRUE(mayControl("127.0.0.1", false));
  EXPECT_TRUE(mayControl("127.0.0.53", false));
  EXPECT_TRUE(mayControl("::1", false));
  EXPECT_TRUE(mayControl("::ffff:127.0.0.1", false));
  EXPECT_FALSE(mayControl("192.168.1.7", false));
  EXPECT_FALSE(mayControl("::ffff:10.0.0.2", false));
  EXPECT_FALSE(mayControl("not an address", false));
  EXPECT_TRUE(mayControl("192.168.1.7", true));
}

TEST(WebViewerRules, PageMessagesAreCheckedBeforeTheyBecomeCommands) {
  const ClientMessage pause = parseClientMessage(R"({"type": "pause"})");
  ASSERT_TRUE(pause.command);
  EXPECT_EQ(pause.command->kind, ViewerCommand::Kind::kPause);
  EXPECT_EQ(parseClientMessage(R"({"type": "resume"})").command->kind, ViewerCommand::Kind::kResume);
  EXPECT_EQ(parseClientMessage(R"({"type": "reset"})").command->kind, ViewerCommand::Kind::kReset);
  EXPECT_TRUE(parseClientMessage(R"({"type": "ack"})").ack);
  const ClientMessage teleop =
      parseClientMessage(R"({"type": "teleop", "robot": "r", "linear": 0.5, "angular": -1})");
  ASSERT_TRUE(teleop.command);
  EXPECT_EQ(teleop.command->robot, "r");
  EXPECT_DOUBLE_EQ(teleop.command->linear, 0.5);
  EXPECT_DOUBLE_EQ(teleop.command->angular, -1);
  EXPECT_EQ(parseClientMessage(R"({"type": "camera", "name": "r/cam"})").camera, std::string("r/cam"));

  for (const char* bad : {"not json", "[1]", R"({"kind": "pause"})", R"({"type": "explode"})",
                                 R"({"type": "teleop", "robot": "r", "linear": "fast", "angular": 0})",
                                 R"({"type": "teleop", "linear": 1, "angular": 0})",
                                 R"({"type": "teleop", "robot": "r", "linear": 1e999, "angular": 0})",
                                 R"({"type": "camera"})"}) {
    const ClientMessage message = parseClientMessage(bad);
    EXPECT_FALSE(message.command) << bad;
    EXPECT_FALSE(message.camera) << bad;
    EXPECT_FALSE(message.error.empty()) << bad;
  }
  EXPECT_THAT(parseClientMessage(R"({"type": "explode"})").error,
              HasSubstr("unknown message type [explode]"));
}

// ---- meshes ----

/// A flat square of n x n cells, two triangles each, every triangle with its own three vertices (as STL).
TriangleMesh unweldedGrid(int n, double side) {
  TriangleMesh mesh;
  const auto corner = [&](int i, int j) { return Eigen::Vector3d(side * i / n, side * j / n, 0); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (const auto& triangle :
           {std::array<std::pair<int, int>, 3>{{{i, j}, {i + 1, j}, {i + 1, j + 1}}},
            std::array<std::pair<int, int>, 3>{{{i, j}, {i + 1, j + 1}, {i, j + 1}}}}) {
        const int first = static_cast<int>(mesh.vertices.size());
        for (const auto& [a, b] : triangle) mesh.vertices.push_back(corner(a, b));
        mesh.triangles.push_back({first, first + 1, first + 2});
      }
    }
  }
  return mesh;
}

TEST(WebViewerMeshes, IdenticalVerticesAreMergedAndSmallMeshesKeepEveryTriangle) {
  const TriangleMesh mesh = unweldedGrid(10, 1.0);
  const SimplifiedMesh simple = simplifyMesh(mesh, 1000);
  EXPECT_EQ(simple.triangles.size(), 200u);
  EXPECT_EQ(simple.vertices.size(), 121u);  // 11 x 11 corners, shared
  for (size_t t = 0; t < simple.triangles.size(); ++t) EXPECT_EQ(simple.source[t], static_cast<int>(t));
}

TEST(WebViewerMeshes, LargeMeshesAreClusteredUnderTheBudgetAndKeepTheirExtent) {
  const TriangleMesh mesh = unweldedGrid(200, 2.0);  // 80,000 triangles
  const SimplifiedMesh simple = simplifyMesh(mesh, 5000);
  EXPECT_LE(simple.triangles.size(), 5000u);
  EXPECT_GE(simple.triangles.size(), 1000u);  // coarser than needed would lose the shape
  Eigen::AlignedBox3f bounds;
  for (const auto& vertex : simple.vertices) bounds.extend(vertex);
  EXPECT_NEAR(bounds.min().x(), 0, 0.1);
  EXPECT_NEAR(bounds.max().x(), 2, 0.1);
  EXPECT_NEAR(bounds.max().y(), 2, 0.1);
  EXPECT_TRUE(std::is_sorted(simple.source.begin(), simple.source.end()));  // parts keep their order
}

// ---- the server over sockets ----

std::string pageDir() { return test::packageFile("bullet_sim", "web"); }

/// A page's side of the WebSocket: connects with an Origin header, reads with a time limit.
class PageClient {
 public:
  PageClient(uint16_t port, const std::string& origin) : ws_(io_) {
    ws_.next_layer().connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    ws_.set_option(websocket::stream_base::decorator(
        [origin](websocket::request_type& request) { request.set(http::field::origin, origin); }));
    ws_.handshake(response_, "127.0.0.1:" + std::to_string(port), "/ws", error_);
  }
  bool open() const { return !error_; }
  beast::error_code error() const { return error_; }

  /// The next message, text or binary. While none comes, calls `idle` (a step and an update of the
  /// simulation) every millisecond; throws after kReadTimeoutSeconds without one.
  std::string read(bool* binary = nullptr, const std::function<void()>& idle = {}) {
    beast::flat_buffer buffer;
    std::optional<beast::error_code> result;
    ws_.async_read(buffer, [&](beast::error_code ec, size_t) { result = ec; });
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kReadTimeoutSeconds);
    while (!result) {
      io_.restart();
      io_.run_for(idle ? std::chrono::milliseconds(1)
                       : std::chrono::milliseconds(1000 * kReadTimeoutSeconds));
      if (result) break;
      if (std::chrono::steady_clock::now() > deadline) {
        ws_.next_layer().close();
        io_.run();
        throw std::runtime_error("the page got no message in " + std::to_string(kReadTimeoutSeconds) + " s");
      }
      if (idle) idle();
    }
    if (*result) throw std::runtime_error("the page could not read: " + result->message());
    if (binary) *binary = ws_.got_binary();
    std::string message = beast::buffers_to_string(buffer.data());
    // As the page does: the server sends the next frame or image when this one is acknowledged.
    if (ws_.got_binary() || message.find(R"("type":"frame")") != std::string::npos) send({{"type", "ack"}});
    return message;
  }
  /// Reads until a text message of `type` for which `accept` holds, calling `idle` while none comes.
  Json readUntil(const std::string& type, const std::function<bool(const Json&)>& accept = {},
                 const std::function<void()>& idle = {}) {
    for (;;) {
      bool binary = false;
      const std::string message = read(&binary, idle);
      if (binary) continue;
      Json json = Json::parse(message);
      if (json["type"] == type && (!accept || accept(json))) return json;
    }
  }
  void send(const Json& message) { ws_.write(net::buffer(message.dump())); }
  /// Drops the connection without a closing handshake, as a browser tab that crashed.
  void vanish() { ws_.next_layer().close(); }

 private:
  net::io_context io_;
  websocket::stream<tcp::socket> ws_;
  websocket::response_type response_;
  beast::error_code error_;
};

/// A GET of `target`, as a browser sends it; with `origin`, a WebSocket upgrade from a page of that origin.
http::response<http::string_body> get(uint16_t port, const std::string& target,
                                      http::verb verb = http::verb::get, const std::string& origin = "") {
  net::io_context io;
  beast::tcp_stream stream(io);
  stream.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> request{verb, target, 11};
  request.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  if (!origin.empty()) {
    request.set(http::field::origin, origin);
    request.set(http::field::connection, "Upgrade");
    request.set(http::field::upgrade, "websocket");
    request.set(http::field::sec_websocket_version, "13");
    request.set(http::field::sec_websocket_key, "dGhlIHNhbXBsZSBub25jZQ==");
  }
  http::write(stream, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(stream, buffer, response);
  return response;
}

/// Commands as the host gets them, on the server's thread.
class CommandLog {
 public:
  WebViewer::CommandSink sink() {
    return [this](const ViewerCommand& command) {
      const std::lock_guard<std::mutex> lock(mutex_);
      commands_.push_back(command);
      changed_.notify_all();
    };
  }
  /// Waits (at most 10 s) for the `count`-th command.
  std::optional<ViewerCommand> waitFor(size_t count) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!changed_.wait_for(lock, std::chrono::seconds(10), [&] { return commands_.size() >= count; }))
      return std::nullopt;
    return commands_[count - 1];
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<ViewerCommand> commands_;
};

WebViewerOptions testOptions() {
  WebViewerOptions options;
  options.page_dir = pageDir();
  options.frame_rate = 1e9;  // a frame after every update: the tests do not wait for the wall clock
  return options;
}

std::string ownOrigin(const WebViewer& viewer) { return "http://127.0.0.1:" + std::to_string(viewer.port()); }

/// Steps and updates until `done` holds, at most `max_steps` steps.
bool stepUntil(Simulation& simulation, WebViewer& viewer, const std::function<bool()>& done,
               int max_steps = 5000) {
  for (int i = 0; i < max_steps; ++i) {
    if (done()) return true;
    simulation.step();
    viewer.update(simulation, false);
  }
  return done();
}

/// A step of the simulation and an update of the viewer: what a page waits on.
std::function<void()> stepper(Simulation& simulation, WebViewer& viewer) {
  return [&simulation, &viewer] {
    simulation.step();
    viewer.update(simulation, false);
  };
}

/// An update of the viewer without a step: a frame of the simulation as it is.
std::function<void()> updater(Simulation& simulation, WebViewer& viewer) {
  return [&simulation, &viewer] { viewer.update(simulation, false); };
}

/// Reads the scene a page is sent first, stepping and updating until it comes.
Json sceneOf(PageClient& page, Simulation& simulation, WebViewer& viewer) {
  EXPECT_TRUE(page.open());
  return page.readUntil("scene", {}, stepper(simulation, viewer));
}

ModelSpec lidarMast() {
  return test::parseQuietly(test::readFile(test::fixture("robots/lidar_mast.urdf")), "lidar_mast.urdf");
}

TEST(WebViewerServer, ServesThePageAndThreeJsAndNothingElse) {
  CommandLog log;
  WebViewer viewer(testOptions(), log.sink());
  const auto page = get(viewer.port(), "/");
  EXPECT_EQ(page.result(), http::status::ok);
  EXPECT_THAT(page.body(), HasSubstr("viewer.js"));
  EXPECT_THAT(std::string(page["Content-Security-Policy"]), HasSubstr("default-src 'self'"));
  EXPECT_EQ(page["X-Frame-Options"], "DENY");
  const auto three = get(viewer.port(), "/three/build/three.module.js");
  EXPECT_EQ(three.result(), http::status::ok);
  EXPECT_THAT(three.body(), HasSubstr("REVISION"));
  EXPECT_EQ(get(viewer.port(), "/viewer.js?v=2").result(), http::status::ok);
  EXPECT_EQ(get(viewer.port(), "/three/../../../etc/passwd").result(), http::status::not_found);
  EXPECT_EQ(get(viewer.port(), "/three/build/three.js").result(), http::status::not_found);
  EXPECT_EQ(get(viewer.port(), "/", http::verb::post).result(), http::status::method_not_allowed);
}

TEST(WebViewerServer, ABusyPortIsOneClearError) {
  CommandLog log;
  WebViewer first(testOptions(), log.sink());
  WebViewerOptions options = testOptions();
  options.port = first.port();
  try {
    WebViewer second(options, log.sink());
    FAIL() << "a second viewer listened on the same port";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot listen on 127.0.0.1:" + std::to_string(first.port())));
    EXPECT_THAT(e.what(), HasSubstr("another program already listens there"));
  }
  options.address = "localhost";
  EXPECT_THROW(WebViewer(options, log.sink()), std::runtime_error);  // an address, not a name
}

TEST(WebViewerServer, AMissingPageOrThreeJsIsAClearError) {
  CommandLog log;
  WebViewerOptions options = testOptions();
  options.three_dir = "/nonexistent/three";
  try {
    WebViewer viewer(options, log.sink());
    FAIL() << "served without three.js";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("libjs-three"));
  }
}

TEST(WebViewerServer, AnotherOriginCannotOpenTheSocket) {
  CommandLog log;
  WebViewer viewer(testOptions(), log.sink());
  PageClient stranger(viewer.port(), "http://evil.example");
  EXPECT_EQ(stranger.error(), websocket::error::upgrade_declined);
  const auto refusal = get(viewer.port(), "/ws", http::verb::get, "http://evil.example");
  EXPECT_EQ(refusal.result(), http::status::forbidden);
  EXPECT_THAT(refusal.body(), HasSubstr("origin [http://evil.example] may not open this viewer"));
  EXPECT_EQ(viewer.viewers(), 0u);
  EXPECT_EQ(get(viewer.port(), "/ws", http::verb::get, ownOrigin(viewer)).result(),
            http::status::switching_protocols);
  PageClient own(viewer.port(), ownOrigin(viewer));
  ASSERT_TRUE(own.open());
  EXPECT_EQ(own.readUntil("hello")["control"], true);  // from this machine
}

TEST(WebViewerServer, APageGetsTheSceneThenFramesWithTheRobotsPoseAndLidarHits) {
  Simulation simulation(test::shippedWorld("test_room.world"));
  Robot& robot = simulation.spawn("mast", lidarMast(), SpawnPose{1.0, 0.5, 0.3});
  CommandLog log;
  WebViewer viewer(testOptions(), log.sink());
  PageClient page(viewer.port(), ownOrigin(viewer));
  const Json scene = sceneOf(page, simulation, viewer);
  const Json& robots = scene["robots"];
  ASSERT_EQ(robots.size(), 1u);
  EXPECT_EQ(robots[0]["name"], "mast");
  EXPECT_EQ(robots[0]["teleop"], false);
  const size_t root = robots[0]["body"];
  EXPECT_EQ(scene["bodies"][root]["name"], "mast::" + robot.body().spec().root);
  EXPECT_FALSE(scene["geometries"].empty());
  EXPECT_FALSE(scene["bounds"].is_null());

  const auto scans = robot.outputs<LaserScan>();
  ASSERT_EQ(scans.size(), 1u);
  ASSERT_TRUE(stepUntil(simulation, viewer, [&] { return scans[0].stream->count() > 0; }));
  const double time = simulation.time();
  const Json frame = page.readUntil("frame", [&](const Json& json) { return json["time"] >= time - 1e-6; },
                                    updater(simulation, viewer));
  EXPECT_EQ(frame["revision"], scene["revision"]);
  const Eigen::Vector3d where = robot.body().linkPose(robot.body().spec().root).translation();
  bool found = false;
  for (size_t i = 0; i < frame["poses"].size(); i += 8) {
    if (frame["poses"][i] != root) continue;
    found = true;
    EXPECT_NEAR(frame["poses"][i + 1].get<double>(), where.x(), 1e-4);
    EXPECT_NEAR(frame["poses"][i + 2].get<double>(), where.y(), 1e-4);
  }
  EXPECT_TRUE(found) << "the robot's root body is in every frame";
  // One hit per finite range, that far from the sensor.
  const LaserScan& scan = scans[0].stream->latest();
  std::vector<double> ranges;
  for (float range : scan.ranges) {
    if (std::isfinite(range)) ranges.push_back(range);
  }
  const Json& hits = frame["hits"];
  ASSERT_EQ(hits.size(), 3 * ranges.size());
  ASSERT_FALSE(ranges.empty());
  for (size_t i = 0; i < ranges.size(); ++i) {
    const Eigen::Vector3d hit(hits[3 * i].get<double>(), hits[3 * i + 1].get<double>(),
                              hits[3 * i + 2].get<double>());
    EXPECT_NEAR((hit - scan.sensor_pose.translation()).norm(), ranges[i], 2e-3);
  }
}

TEST(WebViewerServer, CommandsReachTheHostAndAPageThatLeavesStopsTheRobotItDrove) {
  Simulation simulation(test::shippedWorld("empty.world"));
  simulation.spawn("car", test::parseQuietly(test::twoWheelerWithDiffDrive(), "two_wheeler"), SpawnPose{});
  CommandLog log;
  WebViewer viewer(testOptions(), log.sink());
  {
    PageClient page(viewer.port(), ownOrigin(viewer));
    EXPECT_EQ(sceneOf(page, simulation, viewer)["robots"][0]["teleop"], true);
    page.send({{"type", "pause"}});
    page.send({{"type", "teleop"}, {"robot", "car"}, {"linear", 0.4}, {"angular", 0.2}});
    page.send({{"type", "explode"}});
    EXPECT_THAT(page.readUntil("error")["message"].get<std::string>(), HasSubstr("unknown message type"));
    const auto pause = log.waitFor(1);
    ASSERT_TRUE(pause);
    EXPECT_EQ(pause->kind, ViewerCommand::Kind::kPause);
    const auto drive = log.waitFor(2);
    ASSERT_TRUE(drive);
    EXPECT_EQ(drive->kind, ViewerCommand::Kind::kTeleop);
    EXPECT_DOUBLE_EQ(drive->linear, 0.4);
    page.vanish();
  }
  const auto stop = log.waitFor(3);
  ASSERT_TRUE(stop) << "the page left without a stop";
  EXPECT_EQ(stop->kind, ViewerCommand::Kind::kTeleop);
  EXPECT_EQ(stop->robot, "car");
  EXPECT_EQ(stop->linear, 0);
  EXPECT_EQ(stop->angular, 0);
  EXPECT_TRUE(stepUntil(simulation, viewer, [&] { return viewer.viewers() == 0; }));
}

TEST(WebViewerServer, APageThatStopsReadingNeitherBlocksTheSimulationNorOtherPages) {
  Simulation simulation(test::shippedWorld("test_room.world"));
  simulation.spawn("mast", lidarMast(), SpawnPose{1.0, 0.5, 0.3});
  CommandLog log;
  WebViewerOptions options = testOptions();
  WebViewer viewer(options, log.sink());
  PageClient stuck(viewer.port(), ownOrigin(viewer));
  PageClient reader(viewer.port(), ownOrigin(viewer));
  ASSERT_TRUE(stuck.open() && reader.open());
  // Far more frames than the stuck page takes in; the simulation goes on all the same.
  for (int i = 0; i < 3000; ++i) {
    simulation.step();
    viewer.update(simulation, false);
  }
  const double time = simulation.time();
  const Json frame = reader.readUntil("frame", [&](const Json& json) { return json["time"] >= time - 1e-6; },
                                      updater(simulation, viewer));
  EXPECT_NEAR(frame["time"].get<double>(), time, 1e-6);
  EXPECT_EQ(viewer.viewers(), 2u);
}

TEST(WebViewerServer, APageWatchingACameraGetsItsLatestImage) {
  OffscreenRenderer renderer;
  SimulationOptions options;
  options.images = imagesFrom([&renderer]() -> SceneRenderer& { return renderer; });
  Simulation simulation(test::shippedWorld("empty.world"), options);
  simulation.spawn("box",
                   test::parseQuietly(test::readFile(test::fixture("robots/depth_camera_box.urdf")), "box"),
                   SpawnPose{});
  CommandLog log;
  WebViewer viewer(testOptions(), log.sink());
  PageClient page(viewer.port(), ownOrigin(viewer));
  const Json scene = sceneOf(page, simulation, viewer);
  ASSERT_EQ(scene["cameras"], Json::array({"box/depth_camera"}));
  page.send({{"type", "camera"}, {"name", "box/depth_camera"}});
  for (int i = 0; i < 200; ++i) {  // 0.2 s: the 20 Hz camera renders a few frames
    simulation.step();
    viewer.update(simulation, false);
  }
  for (;;) {
    bool binary = false;
    const std::string message = page.read(&binary, stepper(simulation, viewer));
    if (!binary) continue;
    ASSERT_GT(message.size(), 4u);
    const uint32_t length = static_cast<uint8_t>(message[0]) | static_cast<uint8_t>(message[1]) << 8 |
                            static_cast<uint8_t>(message[2]) << 16 |
                            static_cast<uint32_t>(static_cast<uint8_t>(message[3])) << 24;
    const Json header = Json::parse(message.substr(4, length));
    EXPECT_EQ(header["camera"], "box/depth_camera");
    EXPECT_EQ(header["width"], 640);
    EXPECT_EQ(header["height"], 480);
    EXPECT_EQ(message.size() - 4 - length, static_cast<size_t>(header["step"].get<int>() * 480));
    break;
  }
}

TEST(WebViewerRtf, IsSimSecondsPerWallSecondOverTheLastSecondAndRestartsAfterAReset) {
  RtfMeter meter;
  const auto start = RtfMeter::Clock::time_point{};
  const auto at = [&](double seconds) {
    return start +
           std::chrono::duration_cast<RtfMeter::Clock::duration>(std::chrono::duration<double>(seconds));
  };
  EXPECT_EQ(meter.add(at(0), 0), 0);
  EXPECT_EQ(meter.add(at(0.1), 0.2), 0);  // too short a span to tell
  EXPECT_DOUBLE_EQ(meter.add(at(1.0), 2.0), 2.0);
  for (int i = 11; i <= 30; ++i) meter.add(at(i * 0.1), 2.0 + (i - 10) * 0.05);  // then half speed
  EXPECT_NEAR(meter.add(at(3.1), 3.05), 0.5, 0.06);
  EXPECT_EQ(meter.add(at(3.2), 0.001), 0);  // reset_simulation: time went back
}

}  // namespace
}  // namespace bullet_sim
