// The ROS node `simulator` (registered as `gazebo`, as gzserver is): steps the core in sim time, publishes
// /clock, serves Gazebo's world services and ours, and gives every spawned robot a RobotAdapter.
//
// Params: ~world [empty.world], ~world_fallback [empty.world: the world loaded, with a warning naming the
//   file and its problems, when ~world cannot be found or read, as gzserver falls back on worlds/empty.world;
//   "" makes that an error, as ~strict_models does for a world found but refused], ~strict_models [false: an
//   unknown model:// include is skipped with a warning; true: an error], ~step_size and ~real_time_factor
//   [the world's <physics>: 1 ms, 1; 0 = as fast as possible], ~paused [false], ~seed [0],
//   ~pub_clock_frequency [every step; as Gazebo's, in Hz of sim time; at most 1000 wall Hz, and 10 while
//   paused], ~gui (accepted: rendering is headless), ~snapshot_dir [$ROS_HOME/snapshots], ~snapshot_period
//   [0 sim s = off] (numbered chase-view frames), ~model_states_rate (gazebo_services.h), ~limits/<name>
//   (common/limits.h: what a model or world may ask for), ~record and ~record_* (node_recording.h: a rosbag
//   of the run in sim time), ~web_port and the live viewer's others (web_view.h).
// Services: ~spawn_urdf, ~reset_simulation, ~reset_world, ~pause_physics, ~unpause_physics, ~snapshot (a PNG
//   under ~snapshot_dir; rendered between steps, never inside one), and Gazebo's world API
//   (gazebo_services.h).
#pragma once

#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include "bullet_sim/Snapshot.h"
#include "bullet_sim/SpawnModel.h"
#include "bullet_sim/scene/camera.h"
#include "bullet_sim/scene/recording.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "bullet_sim/scene/scene.h"
#include "bullet_sim/scene/simulation_images.h"
#include "bullet_sim/simulation/simulation.h"
#include "gazebo_services.h"
#include "listened_publisher.h"
#include "node_recording.h"
#include "render_library.h"
#include "robot_adapter.h"
#include "ros_parameters.h"
#include "web_view.h"

namespace bullet_sim {

class SimulatorNode final : public SimulationHost {
 public:
  /// Loads the world named by ~world. Throws std::runtime_error saying what is wrong with it.
  SimulatorNode(ros::NodeHandle node, ros::NodeHandle private_node);

  /// Steps until shutdown. Commands and service calls are handled between steps.
  void run();

  /// Adds a robot with its ROS interface under `robot_namespace`, as ~spawn_urdf does. Throws SpecError.
  Robot& spawnRobot(const std::string& name, ModelSpec model, const SpawnPose& pose,
                    const std::string& robot_namespace, std::vector<std::string>* warnings) override;
  bool deleteRobot(const std::string& name) override;
  bool paused() const override { return paused_; }
  void physicsChanged() override;
  /// For hosts that run the node (the scenario runner): the simulation, a call after every step, and pausing.
  const Simulation& simulation() const { return *simulation_; }
  void observeSteps(std::function<void(const Simulation&)> observer) { observer_ = std::move(observer); }
  /// Paused, the scans still being cast (SimulationOptions::lockstep false) are published at once.
  void setPaused(bool paused);

 private:
  bool spawn(SpawnModel::Request& request, SpawnModel::Response& response);
  bool resetSimulation(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool resetWorld(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool pause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool unpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&);
  bool snapshot(Snapshot::Request& request, Snapshot::Response& response);

  /// The real path of a snapshot file inside ~snapshot_dir, or nullopt with `error` saying why `file` may not
  /// be written: a NUL byte, an absolute path, a way out with .. or through a symbolic link.
  std::optional<std::filesystem::path> snapshotPath(const std::string& file, std::string* error);
  /// Writes what `draw` renders into a PNG at `path`; false with `error` when it cannot.
  bool writeSnapshot(const std::filesystem::path& path, const std::function<Image()>& draw,
                     std::string* error);
  /// The simulation from `view`, with the trails.
  Image drawView(View view, int width, int height);
  /// Extends each robot's trail and writes the periodic frame when one is due.
  void afterStep();

  void step();
  /// Whether /clock is due after a step: Gazebo's ~pub_clock_frequency rule in sim time, at most every 1 ms.
  bool clockDue() const;
  void publishClock();
  /// The renderer of snapshots and cameras, created when first used.
  SceneRenderer& renderer();
  /// Sim time and wall time are matched from now on (after a pause, a reset or a late step).
  void anchorPacing();

  /// Connects and drops the ports that came and went (ros_control's controllers) since the last call.
  void refreshPorts();
  /// Publishes the readings of the rays still being cast behind physics, once they are.
  void publishPendingScans();
  /// The live viewer of ~web_port, with what its pages may do; nullptr when off or when it cannot serve.
  std::unique_ptr<NodeWebView> startWebView();
  /// The resolved name of a robot's velocity input, or "" when it has none.
  std::string velocityTopic(const std::string& robot) const;

  ros::NodeHandle node_;
  ros::NodeHandle private_;
  RosParameters parameters_;  ///< what plugins read at run time; outlives the simulation
  std::unique_ptr<Simulation> simulation_;
  std::unique_ptr<NodeRecording> bag_;  ///< ~record's; closed before the simulation goes
  FrameOwners frame_owners_;  ///< outlives the adapters, which release their frames
  std::map<std::string, std::unique_ptr<RobotAdapter>> adapters_;
  std::unique_ptr<WorldApi> world_api_;  ///< before gazebo_services_, which serves it
  std::unique_ptr<GazeboServices> gazebo_services_;
  ListenedPublisher tf_;  ///< /tf, for every robot
  ros::Publisher clock_;
  std::vector<ros::ServiceServer> services_;

  double real_time_factor_ = 1.0;  ///< the pace: the step size times the physics' max_update_rate
  bool paused_ = false;
  /// [s] of sim time between /clock messages (~pub_clock_frequency); 0: each step
  double clock_sim_period_ = 0;
  ros::WallTime last_clock_;
  double last_clock_sim_ = -std::numeric_limits<double>::infinity();  ///< the first step's time is sent
  ros::WallTime wall_anchor_;
  double sim_anchor_ = 0;

  RenderLibrary render_;  ///< loaded at the first snapshot or camera frame
  std::filesystem::path snapshot_dir_;
  std::unique_ptr<Recording> recording_;  ///< trails and periodic frames (~snapshot_period)
  std::function<void(const Simulation&)> observer_;
  std::unique_ptr<NodeWebView> web_;  ///< destroyed first: its commands call the node
};

}  // namespace bullet_sim
