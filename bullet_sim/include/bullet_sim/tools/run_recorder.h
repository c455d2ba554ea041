// Recording a run into a rosbag, for tools that link no ROS (scenario): this interface is all they see. The
// ROS layer's bag recorder implements it in libbullet_sim_bag.so, which loadBagRecorder loads only when a run
// asks for a bag.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

/// What a bag holds and how it is written; the node's ~record_* parameters say the same.
struct BagSettings {
  std::string path;  ///< FILE.bag (".bag" is added when missing); written as FILE.bag.active until closed
  /// Regular expressions (ECMAScript, matching the whole name) of the topics to record; empty: every topic
  /// but camera images (sensor_msgs/Image) and point clouds (sensor_msgs/PointCloud2 and PointCloud).
  std::vector<std::string> topics;
  std::string compression = "lz4";  ///< "none", "lz4" or "bz2"
  uint32_t chunk_size = 768 * 1024;  ///< [bytes] of messages per chunk, before compression (rosbag's default)
  double ground_truth_rate = 50;     ///< [Hz of sim time] of each robot's <ns>/ground_truth
};

/// Records a simulation's run into a rosbag, stamped and timed in sim time. Messages are converted on the
/// caller's thread, in step order, and written on the recorder's own thread; none is dropped (the caller
/// waits when the writer falls far behind). A path that cannot be written or a write that fails (a full disk)
/// is reported once, and recording stops while the run goes on.
class RunRecorder {
 public:
  virtual ~RunRecorder() = default;

  /// Records `robot` from now on: its topics in `robot_namespace` ("" keeps its plugins' own), its frames
  /// under `tf_prefix` as <ns>/tf_prefix would put them ("" for none). Its fixed links go to /tf_static.
  virtual void addRobot(const Robot& robot, const std::string& robot_namespace,
                        const std::string& tf_prefix) = 0;
  /// Stops recording a robot, before it is removed from the simulation.
  virtual void removeRobot(const std::string& name) = 0;
  /// After every step: what the robots' plugins produced in it, and their ground truth when due.
  virtual void afterStep(const Simulation& simulation) = 0;
  /// A velocity command that `robot`'s `input` took at `sim_time` [s].
  virtual void command(const Robot& robot, const RobotInput<Twist>& input, const Twist& twist,
                       double sim_time) = 0;
  /// After Simulation::resetSimulation: sim time restarts, so the bag is closed and recording goes on into
  /// FILE_1.bag (then FILE_2.bag, ...).
  virtual void restart() = 0;
  /// Writes what is queued, closes the bag and renames it FILE.bag. The bags written so far (FILE.bag,
  /// FILE_1.bag, ...); empty when recording stopped on an error.
  virtual std::vector<std::string> close() = 0;
};

/// Reports a recording's error (it names the path), once.
using RecorderErrors = std::function<void(const std::string& error)>;

/// A recorder writing `settings.path`, from libbullet_sim_bag.so. Throws std::invalid_argument naming a bad
/// setting, and std::runtime_error when the library cannot be loaded. A path that cannot be written goes to
/// `errors`, and the recorder records nothing.
std::unique_ptr<RunRecorder> loadBagRecorder(const BagSettings& settings, RecorderErrors errors);

}  // namespace bullet_sim
