#include "simulator_node.h"

#include <malloc.h>
#include <ros/callback_queue.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "bullet_sim/tools/process_stats.h"

namespace bullet_sim {

namespace {

constexpr int kMaxSnapshotSide = 4096;  // [px]
constexpr int kMostThreads = 64;        // ~threads, as bench's --threads
/// /clock at most this often in wall time: a run at RTF 300 would otherwise send every node that takes the
/// time 300,000 messages a second.
const ros::WallDuration kClockWallPeriod(0.001);
/// /clock while paused: the time stands, and a node that starts then learns it within this.
const ros::WallDuration kPausedClockPeriod(0.1);

std::filesystem::path defaultSnapshotDir() {
  const char* ros_home = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  const std::filesystem::path base =
      ros_home ? ros_home : std::filesystem::path(home ? home : "/tmp") / ".ros";
  return base / "snapshots";
}

/// ~threads: the threads that cast each step's due scans in lockstep, solve its islands side by side and
/// split a spawn's meshes (SimulationOptions::threads); 0, the default, takes the cores the node may run on,
/// at most 4. A whole number given as a double (2.0) counts, as roscpp's own integer parameters take it.
int threadsParam(const ros::NodeHandle& private_node) {
  XmlRpc::XmlRpcValue given;
  if (!private_node.getParam("threads", given)) return 0;
  double count = -1;
  if (given.getType() == XmlRpc::XmlRpcValue::TypeInt) count = static_cast<int>(given);
  if (given.getType() == XmlRpc::XmlRpcValue::TypeDouble) count = static_cast<double>(given);
  if (count >= 0 && count <= kMostThreads && count == std::floor(count)) return static_cast<int>(count);
  throw std::runtime_error(
      "~threads must be a whole number from 0 (the cores the node may run on, at most 4) to " +
      std::to_string(kMostThreads) + ", not " + describeParam(given));
}

/// ~seed: any whole number, as gzserver's --seed takes any; a negative one with a warning, as the unsigned
/// seed it wraps to.
uint64_t seedParam(const ros::NodeHandle& private_node) {
  const int seed = wholeParam(private_node, "seed", 0);
  const auto taken = static_cast<uint64_t>(static_cast<int64_t>(seed));
  if (seed < 0) {
    ROS_WARN("~seed %d is negative: taken as the unsigned seed %llu", seed,
             static_cast<unsigned long long>(taken));
  }
  return taken;
}

/// The limits, each from its ~limits/<name> when set.
Limits limitsParam(const ros::NodeHandle& private_node) {
  Limits limits;
  for (const std::string& name : Limits::names()) {
    const std::optional<double> value = numberParamIfSet(private_node, "limits/" + name);
    if (!value) continue;
    try {
      limits.set(name, *value);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error("~limits/" + name + ": " + e.what());
    }
  }
  return limits;
}

WorldSpec loadWorldParam(const ros::NodeHandle& private_node, const Limits& limits) {
  const std::string name = textParam(private_node, "world", "empty.world");
  const std::string fallback = textParam(private_node, "world_fallback", "empty.world");
  WorldOptions options;
  options.strict_models = flagParam(private_node, "strict_models", false);
  options.limits = limits;
  std::vector<std::string> warnings;
  std::string path;
  try {
    WorldSpec world =
        loadWorldOrFallback(name, fallback, PackageResolver::fromEnvironment(), &warnings, options, &path);
    for (const auto& warning : warnings) ROS_WARN("%s", warning.c_str());
    ROS_INFO("world %s", path.c_str());
    return world;
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("~world: ") + e.what());
  }
}

}  // namespace

SimulatorNode::SimulatorNode(ros::NodeHandle node, ros::NodeHandle private_node)
    : node_(node),
      private_(private_node),
      tf_(ListenedPublisher::advertise<tf2_msgs::TFMessage>(node_, "/tf", 100)) {
  SimulationOptions options;
  options.limits = limitsParam(private_);
  WorldSpec world = loadWorldParam(private_, options.limits);
  // The world's <physics>, unless the node's own parameters say otherwise.
  options.physics.step_size = numberParam(private_, "step_size", world.max_step_size);
  real_time_factor_ =
      numberParam(private_, "real_time_factor", world.real_time_update_rate * world.max_step_size);
  options.seed = seedParam(private_);
  options.threads = threadsParam(private_);
  options.lockstep = flagParam(private_, "lockstep", false);
  paused_ = flagParam(private_, "paused", false);
  const double clock_frequency = numberParam(private_, "pub_clock_frequency", 0.0);
  if (clock_frequency < 0) ROS_WARN("~pub_clock_frequency %g: /clock at every step, as 0", clock_frequency);
  clock_sim_period_ = clock_frequency > 0 ? 1.0 / clock_frequency : 0.0;
  if (options.physics.step_size <= 0 || !std::isfinite(options.physics.step_size)) {
    throw std::runtime_error("~step_size must be a positive number of seconds");
  }
  if (real_time_factor_ < 0 || !std::isfinite(real_time_factor_)) {
    throw std::runtime_error("~real_time_factor must be >= 0 (0 runs as fast as possible)");
  }
  if (flagParam(private_, "gui", false)) {
    ROS_INFO(
        "gui:=true is accepted, but bullet_sim renders headless: use its snapshot service or render_model");
  }
  options.images = imagesFrom([this]() -> SceneRenderer& { return renderer(); });
  options.parameters = &parameters_;
  simulation_ = std::make_unique<Simulation>(std::move(world), options);
  bag_ = NodeRecording::fromParameters(private_, [this] { return simulation_->time(); });
  world_api_ = std::make_unique<WorldApi>(*simulation_, real_time_factor_ / options.physics.step_size);
  gazebo_services_ = std::make_unique<GazeboServices>(private_, *simulation_, *world_api_, *this);
  snapshot_dir_ = textParam(private_, "snapshot_dir", defaultSnapshotDir().string());
  recording_ = std::make_unique<Recording>(std::max(0.0, numberParam(private_, "snapshot_period", 0.0)));

  clock_ = node_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  services_.push_back(private_.advertiseService("spawn_urdf", &SimulatorNode::spawn, this));
  services_.push_back(private_.advertiseService("reset_simulation", &SimulatorNode::resetSimulation, this));
  services_.push_back(private_.advertiseService("reset_world", &SimulatorNode::resetWorld, this));
  services_.push_back(private_.advertiseService("pause_physics", &SimulatorNode::pause, this));
  services_.push_back(private_.advertiseService("unpause_physics", &SimulatorNode::unpause, this));
  services_.push_back(private_.advertiseService("snapshot", &SimulatorNode::snapshot, this));
  web_ = startWebView();
}

std::unique_ptr<NodeWebView> SimulatorNode::startWebView() {
  NodeWebView::Actions actions;
  actions.pause = [this] { setPaused(true); };
  actions.resume = [this] { setPaused(false); };
  actions.reset = [this] {
    std_srvs::Empty::Request request;
    std_srvs::Empty::Response response;
    resetSimulation(request, response);
  };
  actions.velocity_topic = [this](const std::string& robot) { return velocityTopic(robot); };
  return NodeWebView::fromParameters(private_, std::move(actions));
}

std::string SimulatorNode::velocityTopic(const std::string& robot) const {
  const Robot* found = simulation_->robot(robot);
  const auto adapter = adapters_.find(robot);
  if (!found || adapter == adapters_.end()) return "";
  const auto inputs = found->inputs<Twist>();
  return inputs.empty() ? "" : adapter->second->topicName(*inputs.front().plugin, inputs.front().topic);
}

void SimulatorNode::run() {
  // /clock is never 0: the first step happens even when starting paused.
  step();
  anchorPacing();
  ROS_INFO("first /clock %.3f s after the process started (%.3f s of CPU), %.0f MB of memory at most so far",
           processAge().value_or(NAN), cpuSeconds(), peakRssMb());
  ros::CallbackQueue& queue = *ros::getGlobalCallbackQueue();
  while (ros::ok()) {
    queue.callAvailable();  // commands and service calls land between steps
    refreshPorts();         // a controller loaded while paused is heard at once
    if (paused_) {
      if (web_) web_->update(*simulation_, paused_);
      if (ros::WallTime::now() - last_clock_ >= kPausedClockPeriod) publishClock();
      queue.callAvailable(kClockWallPeriod);
      continue;
    }
    if (real_time_factor_ > 0) {
      const ros::WallTime due =
          wall_anchor_ + ros::WallDuration((simulation_->time() - sim_anchor_) / real_time_factor_);
      const ros::WallTime now = ros::WallTime::now();
      if (now < due) {
        queue.callAvailable(due - now);  // wait for the wall clock, still answering callbacks
        continue;
      }
      if ((now - due).toSec() > 0.1) anchorPacing();  // far behind real time: do not try to catch up
    }
    step();
  }
}

void SimulatorNode::step() {
  simulation_->step();
  for (auto& [name, adapter] : adapters_) adapter->publish();
  if (bag_) bag_->afterStep(*simulation_);
  gazebo_services_->afterStep();
  if (clockDue()) publishClock();
  afterStep();
}

void SimulatorNode::afterStep() {
  if (observer_) observer_(*simulation_);
  if (web_) web_->update(*simulation_, paused_);
  if (const auto frame = recording_->afterStep(*simulation_)) {
    std::string error;
    if (!writeSnapshot(
            snapshot_dir_ / *frame, [this] { return drawView(View::kChase, 640, 480); }, &error)) {
      ROS_WARN_THROTTLE(10, "~snapshot_period: %s", error.c_str());
    }
  }
}

void SimulatorNode::refreshPorts() {
  for (auto& [name, adapter] : adapters_) adapter->refreshPorts();
}

bool SimulatorNode::clockDue() const {
  if (ros::WallTime::now() - last_clock_ < kClockWallPeriod) return false;
  const double since = simulation_->time() - last_clock_sim_;
  // Gazebo's rule: every step, or once ~pub_clock_frequency's period of sim time has passed. A reset that
  // took the time back is told at once.
  return since < 0 || since >= clock_sim_period_ - 1e-9;
}

void SimulatorNode::publishClock() {
  rosgraph_msgs::Clock clock;
  clock.clock = ros::Time(simulation_->time());
  clock_.publish(clock);
  last_clock_ = ros::WallTime::now();
  last_clock_sim_ = simulation_->time();
}

void SimulatorNode::anchorPacing() {
  wall_anchor_ = ros::WallTime::now();
  sim_anchor_ = simulation_->time();
}

Robot& SimulatorNode::spawnRobot(const std::string& name, ModelSpec model, const SpawnPose& pose,
                                 const std::string& robot_namespace, std::vector<std::string>* warnings) {
  const std::string source = "model [" + name + "]";
  Robot& robot = simulation_->spawn(name, std::move(model), pose, warnings);
  std::unique_ptr<RobotAdapter> adapter;
  try {
    adapter =
        std::make_unique<RobotAdapter>(robot, robot_namespace, tf_, frame_owners_,
                                             [this] { return simulation_->time(); });
  } catch (...) {
    simulation_->remove(name);
    throw;
  }
  for (const auto& warning : *warnings) ROS_WARN("%s: %s", source.c_str(), warning.c_str());
  for (const auto& topic : adapter->topics()) ROS_INFO("%s: %s", source.c_str(), topic.c_str());
  // What the plugins could not connect, warned already, goes into the spawn's answer too.
  warnings->insert(warnings->end(), adapter->problems().begin(), adapter->problems().end());
  ROS_INFO("%s: %s", source.c_str(), simulation_->substepNote(name).c_str());
  adapters_[name] = std::move(adapter);
  if (bag_) bag_->addRobot(robot, robot_namespace);
  if (web_) web_->modelsChanged();
  return robot;
}

bool SimulatorNode::deleteRobot(const std::string& name) {
  publishPendingScans();  // the robot's last scan too
  adapters_.erase(name);
  if (bag_) bag_->removeRobot(name);
  recording_->forget(name);
  const bool removed = simulation_->remove(name);
  if (web_) web_->modelsChanged();
  malloc_trim(0);  // the robot's memory goes back to the system, not only to malloc
  return removed;
}

void SimulatorNode::physicsChanged() {
  const PhysicsProperties physics = world_api_->physicsProperties();
  real_time_factor_ = physics.step_size * physics.max_update_rate;
  anchorPacing();
}

void SimulatorNode::setPaused(bool paused) {
  paused_ = paused;
  if (paused_) publishPendingScans();
  if (!paused_) anchorPacing();
}

void SimulatorNode::publishPendingScans() {
  simulation_->finishCasts();
  for (auto& [name, adapter] : adapters_) adapter->publish();
  if (bag_) bag_->afterStep(*simulation_);  // recorded too, in the bag of their time
}

bool SimulatorNode::spawn(SpawnModel::Request& request, SpawnModel::Response& response) {
  const std::string source = "model [" + request.model_name + "]";
  ROS_INFO("spawning %s", source.c_str());
  try {
    std::vector<std::string> warnings;
    if (request.joint_names.size() != request.joint_positions.size()) {
      throw std::invalid_argument("joint_names and joint_positions differ in length");
    }
    Diagnostics pose_problems(source);
    const auto& at = request.initial_pose;
    SpawnPose pose = spawnPoseFrom(
        Eigen::Vector3d(at.position.x, at.position.y, at.position.z),
        Eigen::Quaterniond(at.orientation.w, at.orientation.x, at.orientation.y, at.orientation.z),
        request.place_on_ground, pose_problems);
    pose_problems.throwIfErrors();
    warnings = pose_problems.warnings();
    ModelSpec model = parseModel(request.model_xml, source, PackageResolver::fromEnvironment(), &warnings,
                                 simulation_->limits(), flagParam(private_, "strict_models", false));
    if (!request.robot_namespace.empty()) pose.robot_namespace = request.robot_namespace;
    for (size_t i = 0; i < request.joint_names.size(); ++i) {
      pose.joints[request.joint_names[i]] = request.joint_positions[i];
    }
    spawnRobot(request.model_name, std::move(model), pose, request.robot_namespace, &warnings);
    response.success = true;
    response.message = "spawned " + source;
    for (const auto& warning : warnings) response.message += "\n" + warning;
  } catch (const std::exception& e) {
    response.success = false;
    response.message = e.what();
    ROS_ERROR("spawn refused: %s", e.what());
    malloc_trim(0);  // what the refused model took goes back to the system
  }
  return true;
}

bool SimulatorNode::resetSimulation(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  publishPendingScans();  // before time restarts
  simulation_->resetSimulation();
  recording_->restart();
  if (bag_) bag_->restart();  // sim time restarts: FILE_1.bag
  step();  // time restarts at the first step, and /clock is never 0
  anchorPacing();
  return true;
}

bool SimulatorNode::resetWorld(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  simulation_->resetWorld();
  recording_->clearTrails();
  return true;
}

bool SimulatorNode::pause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  setPaused(true);
  return true;
}

bool SimulatorNode::unpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  setPaused(false);
  return true;
}

bool SimulatorNode::snapshot(Snapshot::Request& request, Snapshot::Response& response) {
  const auto refuse = [&](const std::string& why) {
    response.success = false;
    response.message = why;
    ROS_WARN("~snapshot refused: %s", why.c_str());
    return true;
  };
  const std::string view_name = request.view.empty() ? "chase" : request.view;
  const auto view = parseView(view_name);
  const auto camera = parseCameraView(view_name);
  if (!view && !camera) {
    return refuse("unknown view [" + request.view + "]: use chase, top, front, camera:NAME or depth:NAME");
  }
  if (request.width > kMaxSnapshotSide || request.height > kMaxSnapshotSide) {
    return refuse("size " + std::to_string(request.width) + " x " + std::to_string(request.height) +
                  " is above " + std::to_string(kMaxSnapshotSide) + " x " + std::to_string(kMaxSnapshotSide));
  }
  const int width = request.width == 0 ? 640 : static_cast<int>(request.width);
  const int height = request.height == 0 ? 480 : static_cast<int>(request.height);
  std::string error;
  const auto path = snapshotPath(request.file, &error);
  if (!path) return refuse(error);
  const auto draw = [&] {
    return camera ? cameraImage(*simulation_, *camera, renderer()) : drawView(*view, width, height);
  };
  if (!writeSnapshot(*path, draw, &error)) return refuse(error);
  response.success = true;
  response.path = path->string();
  response.message = "wrote " + response.path;
  return true;
}

std::optional<std::filesystem::path> SimulatorNode::snapshotPath(const std::string& file,
                                                                 std::string* error) {
  namespace fs = std::filesystem;
  const std::string inside = "must be a relative path inside ~snapshot_dir [" + snapshot_dir_.string() + "]";
  if (file.find('\0') != std::string::npos) {
    *error = "file [" + file.substr(0, file.find('\0')) + "\\0...] holds a NUL byte: a file name cannot";
    return std::nullopt;
  }
  const fs::path relative = fs::path(file).lexically_normal();
  if (file.empty() || relative.is_absolute() || relative.empty() || *relative.begin() == "..") {
    *error = "file [" + file + "] " + inside;
    return std::nullopt;
  }
  // Symbolic links inside the folder may lead out of it: the real path must stay inside the real folder.
  std::error_code ec;
  fs::create_directories(snapshot_dir_, ec);
  const fs::path folder = fs::canonical(snapshot_dir_, ec);
  if (ec) {
    *error = "~snapshot_dir [" + snapshot_dir_.string() + "] cannot be created: " + ec.message();
    return std::nullopt;
  }
  const fs::path real = fs::weakly_canonical(folder / relative, ec);
  const auto [end, ignored] = std::mismatch(folder.begin(), folder.end(), real.begin(), real.end());
  bool dangling_link = false;  // weakly_canonical resolves the links that lead somewhere; these do not
  for (fs::path at = real; !ec && end == folder.end() && at != folder; at = at.parent_path()) {
    std::error_code missing;  // what does not exist yet is no link
    dangling_link |= fs::is_symlink(fs::symlink_status(at, missing));
  }
  if (ec || end != folder.end() || real == folder || dangling_link) {
    *error = "file [" + file + "] leads to [" + real.string() + "] through a symbolic link: it " + inside;
    return std::nullopt;
  }
  return real;
}

Image SimulatorNode::drawView(View view, int width, int height) {
  return renderer().render(simulationScene(*simulation_, view, "", recording_->trails()), width, height);
}

bool SimulatorNode::writeSnapshot(const std::filesystem::path& path, const std::function<Image()>& draw,
                                  std::string* error) {
  try {
    std::filesystem::create_directories(path.parent_path());
    const Image image = draw();
    return render_.writePng(path.string(), image, error);
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
}

SceneRenderer& SimulatorNode::renderer() { return render_.renderer(); }

}  // namespace bullet_sim
