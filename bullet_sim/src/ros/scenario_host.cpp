// scenario_host: the simulator node of a launch scenario, started by `scenario` through roslaunch (it is no
// tool of its own). It is the `simulator` node, with the scenario's world, robots, seed and pace; it holds
// the clock until the user's nodes publish what the scenario waits for, records the run as the in-process
// runner does, stops after the scenario's duration and writes result.json. Exit status: that of `scenario`.
#include <ros/ros.h>
#include <topic_tools/shape_shifter.h>

#include <iostream>

#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scenario/scenario_command.h"
#include "bullet_sim/scenario/scenario_run.h"
#include "simulator_node.h"

namespace bullet_sim {
namespace {

constexpr double kReadyPoll = 0.02;  ///< [s] of wall time between looks at the master

/// The topics the clock waits for: the scenario's, else every robot's cmd_vel (each Twist input).
std::vector<std::string> awaitedTopics(const ScenarioSpec& spec, const Simulation& simulation) {
  std::vector<std::string> topics;
  for (const auto& topic : spec.launch->wait_for) topics.push_back(ros::names::resolve(topic));
  if (!topics.empty()) return topics;
  const std::vector<std::string> robots = simulation.robotNames();
  for (const auto& name : robots) {
    const std::string prefix = robots.size() > 1 ? "/" + name + "/" : "/";
    for (const auto& plugin : simulation.robot(name)->plugins()) {
      for (const InputPort& port : plugin->ports().inputs) {
        if (std::holds_alternative<InputHandler<Twist>>(port.sink))
          topics.push_back(ros::names::clean(prefix + plugin->robotNamespace() + "/" + port.topic));
      }
    }
  }
  return topics;
}

/// Subscriptions to the awaited topics, of any type. roscpp shares one connection per topic within a process,
/// so a publisher connected here is connected to the simulator's own subscriber too.
class Readiness {
 public:
  explicit Readiness(const std::vector<std::string>& topics) {
    ros::NodeHandle node;
    for (const auto& topic : topics) {
      const boost::function<void(const topic_tools::ShapeShifter::ConstPtr&)> ignore =
          [](const topic_tools::ShapeShifter::ConstPtr&) {};
      subscribers_.push_back(node.subscribe<topic_tools::ShapeShifter>(topic, 1, ignore));
    }
  }
  /// The first awaited topic that no publisher is connected to yet; "" when all are.
  std::string silentTopic() const {
    for (const auto& subscriber : subscribers_) {
      if (subscriber.getNumPublishers() == 0) return subscriber.getTopic();
    }
    return "";
  }

 private:
  std::vector<ros::Subscriber> subscribers_;
};

/// Sets the node's parameters from the scenario: its world, step, seed and pace, paused until ready, in
/// lockstep, and the bag --bag asks for.
void setParameters(const ros::NodeHandle& node, const ScenarioSpec& spec,
                   const std::optional<BagSettings>& bag) {
  node.setParam("world", spec.world);
  node.setParam("step_size", spec.step);
  node.setParam("seed", static_cast<int>(spec.seed));
  node.setParam("real_time_factor", spec.launch->real_time_factor);
  node.setParam("paused", true);
  node.setParam("lockstep", true);  // scans as the in-process run has them, none still cast at the end
  if (!bag) return;
  node.setParam("record", bag->path);
  if (!bag->topics.empty()) node.setParam("record_topics", bag->topics);
  node.setParam("record_compression", bag->compression);
  node.setParam("record_chunk_size", static_cast<int>(bag->chunk_size));
}

int host(const ScenarioCommand& command) {
  RunContext context;
  context.mode = "launch";
  const ScenarioSpec spec = commandScenario(command, PackageResolver::fromEnvironment(), &context);
  context.spec = &spec;
  context.launch_log = "launch.log";
  const std::string out = outputFolder(command, &spec);
  RunTiming timing;
  ros::NodeHandle private_node("~");
  setParameters(private_node, spec, bagSettings(command, out));
  SimulatorNode node(ros::NodeHandle(), private_node);
  const ScenarioAssets assets = loadAssets(spec, PackageResolver::fromEnvironment());
  std::vector<std::string> warnings = assets.warnings;
  for (size_t i = 0; i < assets.robot_names.size(); ++i) {
    const std::string& name = assets.robot_names[i];
    node.spawnRobot(name, assets.model, spec.spawn[i], assets.robot_names.size() > 1 ? name : "", &warnings);
  }
  ScenarioMonitor monitor(spec, node.simulation(), warnings);
  OffscreenRenderer renderer;
  std::unique_ptr<ScenarioVideo> video;
  if (command.video) video = std::make_unique<ScenarioVideo>(out + "/video.mp4", spec, renderer);
  const Readiness readiness(awaitedTopics(spec, node.simulation()));
  const long steps = std::lround(spec.duration / spec.step);
  std::string failure;
  auto stepping = std::chrono::steady_clock::now();
  node.observeSteps([&](const Simulation& simulation) {
    monitor.afterStep(simulation);
    if (video) video->afterStep(simulation, monitor);
    if (static_cast<long>(simulation.steps()) >= steps) ros::shutdown();
  });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(spec.launch->ready_timeout);
  ros::WallTimer ready =
      ros::NodeHandle().createWallTimer(ros::WallDuration(kReadyPoll), [&](const ros::WallTimerEvent&) {
        const std::string silent = readiness.silentTopic();
        if (silent.empty()) {
          timing.setup =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - timing.start).count();
          stepping = std::chrono::steady_clock::now();
          node.setPaused(false);
          ready.stop();
        } else if (ros::WallTime::now() > deadline) {
          failure = "the launch's nodes were not ready after " + std::to_string(spec.launch->ready_timeout) +
                    " s: nobody publishes [" + silent + "] (drive.launch.wait_for)";
          ros::shutdown();
        }
      });
  node.run();
  if (!failure.empty()) {
    writeErrorResult(out, context, failure);
    std::cerr << "scenario_host: " << failure << std::endl;
    return static_cast<int>(Verdict::kError);
  }
  if (video) video->finish();
  timing.stepping = std::chrono::duration<double>(std::chrono::steady_clock::now() - stepping).count();
  timing.sim_time = node.simulation().time();
  return static_cast<int>(writeOutputs(out, context, monitor, node.simulation(), renderer, timing));
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  ros::init(argc, argv, "gazebo", ros::init_options::NoSigintHandler);
  bullet_sim::ScenarioCommand command;
  try {
    command = bullet_sim::parseScenarioCommand(argc, argv);
    return bullet_sim::host(command);
  } catch (const std::exception& error) {
    std::cerr << "scenario_host: " << error.what() << std::endl;
    try {
      bullet_sim::RunContext context;
      bullet_sim::writeErrorResult(command.out.empty() ? "." : command.out, context, error.what());
    } catch (const std::exception&) {
    }
    return static_cast<int>(bullet_sim::Verdict::kError);
  }
}
