#include "bullet_sim/scenario/scenario_run.h"

#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/camera.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "bullet_sim/scene/simulation_images.h"
#include "bullet_sim/scenario/video_writer.h"
#include "bullet_sim/tools/urdf_edits.h"
#include "bullet_sim/tools/xacro_cache.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

constexpr double kCommandPeriod = 0.1;  ///< [s]: cmd_vel is re-sent as `rostopic pub -r 10` does

bool endsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read robot.description [" + path + "]");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

std::string verdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kPass: return "pass";
    case Verdict::kFail: return "fail";
    case Verdict::kError: return "error";
  }
  return "error";
}

ScenarioAssets loadAssets(const ScenarioSpec& spec, const PackageResolver& resolver) {
  ScenarioAssets assets;
  std::string urdf = endsWith(spec.description, ".xacro") ? cachedXacro(spec.description, spec.xacro_args)
                                                          : readFile(spec.description);
  if (spec.wheel_model) urdf = withWheelModel(urdf, *spec.wheel_model);
  assets.model = parseModel(urdf, spec.description, resolver, &assets.warnings);
  assets.urdf = std::move(urdf);
  assets.world = loadWorld(spec.world, resolver, &assets.warnings);
  assets.robot_names = spec.robotNames(assets.model.name);
  return assets;
}

void spawnRobots(Simulation& simulation, const ScenarioSpec& spec, const ScenarioAssets& assets,
                 std::vector<std::string>* warnings) {
  for (size_t i = 0; i < assets.robot_names.size(); ++i)
    simulation.spawn(assets.robot_names[i], assets.model, spec.spawn[i], warnings);
}

TimelineDriver::TimelineDriver(const ScenarioSpec& spec, const Simulation& simulation)
    : segments_(spec.timeline), robots_(simulation.robotNames()) {
  double start = 0;
  for (size_t i = 0; i < segments_.size(); ++i) {
    starts_.push_back(start);
    start += segments_[i].duration;
    const std::string& robot = segments_[i].robot;
    if (!robot.empty() && !simulation.robot(robot)) {
      throw ScenarioError("scenario " + spec.source + ": drive.timeline." + std::to_string(i) +
                          ".robot: no robot [" + robot + "] in this run" + didYouMean(robot, robots_));
    }
  }
  for (const auto& name : robots_) {
    if (!segments_.empty() && simulation.robot(name)->inputs<Twist>().empty()) {
      throw ScenarioError(
          "scenario " + spec.source + ": robot [" + name +
          "] takes no cmd_vel: its description declares no drive plugin for the timeline to drive");
    }
  }
  steps_per_resend_ = std::max(1L, std::lround(kCommandPeriod / simulation.stepSize()));
}

void TimelineDriver::beforeStep(const Simulation& simulation, RunRecorder* recorder) {
  if (segments_.empty() || simulation.steps() % steps_per_resend_ != 0) return;
  const double now = simulation.time();
  for (const auto& name : robots_) {
    Twist command;  // after the last segment: stop
    for (size_t i = segments_.size(); i-- > 0;) {
      const TimelineSegment& segment = segments_[i];
      if ((!segment.robot.empty() && segment.robot != name) || now + 1e-9 < starts_[i]) continue;
      if (now + 1e-9 < starts_[i] + segment.duration)
        command.linear = Eigen::Vector3d(segment.v, segment.vy, 0);
      if (now + 1e-9 < starts_[i] + segment.duration) command.angular.z() = segment.w;
      break;
    }
    const Robot* robot = simulation.robot(name);
    for (const RobotInput<Twist>& input : robot->inputs<Twist>()) {
      (*input.handler)(command, now);
      if (recorder) recorder->command(*robot, input, command, now);
    }
  }
}

ScenarioVideo::ScenarioVideo(const std::string& path, const ScenarioSpec& spec, SceneRenderer& renderer)
    : writer_(std::make_unique<VideoWriter>(path, spec.video_width, spec.video_height,
                                            static_cast<int>(std::lround(spec.video_fps)))),
      width_(spec.video_width), height_(spec.video_height), renderer_(renderer),
      period_(1.0 / std::lround(spec.video_fps)), next_(period_) {}

ScenarioVideo::~ScenarioVideo() = default;

void ScenarioVideo::afterStep(const Simulation& simulation, const ScenarioMonitor& monitor) {
  if (simulation.time() + 1e-9 < next_) return;
  next_ += period_;  // (frames that a step longer than the period skips are not made up)
  const Scene scene = simulationScene(simulation, View::kChase, "", monitor.trails().trails());
  writer_->add(renderer_.render(scene, width_, height_));
}

void ScenarioVideo::finish() { writer_->finish(); }

std::unique_ptr<RunRecorder> recordRobots(const BagSettings& settings, const Simulation& simulation) {
  auto recorder =
      loadBagRecorder(settings, [](const std::string& error) { std::cerr << "scenario: " << error << "\n"; });
  const std::vector<std::string> robots = simulation.robotNames();
  for (const auto& name : robots) {
    const std::string own = robots.size() > 1 ? name : "";
    recorder->addRobot(*simulation.robot(name), own, own);
  }
  return recorder;
}

Verdict runTimeline(const ScenarioSpec& spec, const RunContext& context, const std::string& out, bool video,
                    const std::optional<BagSettings>& bag) {
  RunTiming timing;
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  ScenarioAssets assets = loadAssets(spec, resolver);
  OffscreenRenderer renderer;
  SimulationOptions options;
  options.physics.step_size = spec.step;
  options.seed = spec.seed;
  options.images = imagesFrom([&renderer]() -> SceneRenderer& { return renderer; });
  Simulation simulation(assets.world, options);
  std::vector<std::string> warnings = assets.warnings;
  spawnRobots(simulation, spec, assets, &warnings);
  ScenarioMonitor monitor(spec, simulation, warnings);
  TimelineDriver driver(spec, simulation);
  std::error_code ec;
  fs::create_directories(out, ec);
  std::unique_ptr<ScenarioVideo> scenario_video;
  if (video)
    scenario_video = std::make_unique<ScenarioVideo>((fs::path(out) / "video.mp4").string(), spec, renderer);
  const std::unique_ptr<RunRecorder> bag_recorder = bag ? recordRobots(*bag, simulation) : nullptr;
  timing.setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - timing.start).count();

  const auto stepping = std::chrono::steady_clock::now();
  const long steps = std::lround(spec.duration / spec.step);
  for (long i = 0; i < steps; ++i) {
    driver.beforeStep(simulation, bag_recorder.get());
    simulation.step();
    monitor.afterStep(simulation);
    if (scenario_video) scenario_video->afterStep(simulation, monitor);
    if (bag_recorder) bag_recorder->afterStep(simulation);
  }
  if (scenario_video) scenario_video->finish();
  if (bag_recorder) bag_recorder->close();
  timing.stepping = std::chrono::duration<double>(std::chrono::steady_clock::now() - stepping).count();
  timing.sim_time = simulation.time();
  return writeOutputs(out, context, monitor, simulation, renderer, timing);
}

}  // namespace bullet_sim
