// The bag recorder behind the node's ~record and scenario's --bag: a run's robots as ROS would see them, in
// one rosbag whose time is sim time. Per robot: every plugin output as the node publishes it (sensors,
// odometry, the odom -> base transforms on /tf), its commands, its links as robot_state_publisher publishes
// them (fixed joints on a latched /tf_static, moving ones on /tf with each joint_states sample) and its
// ground truth (<ns>/ground_truth, nav_msgs/Odometry of its root link in `world`). /clock is not recorded:
// `rosbag play --clock` makes it from the bag's time. The bag holds no wall time, caller id or host name, so
// a deterministic run gives the same bytes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bag_writer.h"
#include "bullet_sim/tools/run_recorder.h"
#include "robot_recording.h"

namespace bullet_sim {

class BagRecorder final : public RunRecorder {
 public:
  /// Throws std::invalid_argument naming a bad setting. A path that cannot be written goes to `errors`, and
  /// nothing is recorded.
  BagRecorder(BagSettings settings, RecorderErrors errors);
  ~BagRecorder() override;

  void addRobot(const Robot& robot, const std::string& robot_namespace,
                const std::string& tf_prefix) override;
  /// Records `robot`, named as `names` say (the node's parameters).
  void addRobot(const Robot& robot, RobotNames names);
  void removeRobot(const std::string& name) override;
  void afterStep(const Simulation& simulation) override;
  void command(const Robot& robot, const RobotInput<Twist>& input, const Twist& twist,
               double sim_time) override;
  /// A command as the node received it on `topic`, at `sim_time` [s].
  void command(const std::string& topic, const topic_tools::ShapeShifter::ConstPtr& message, double sim_time);
  void restart() override;
  std::vector<std::string> close() override;

  /// The topics `robot` takes commands on that the bag records.
  std::vector<CommandTopic> commandTopics(const std::string& robot) const;
  /// The bag being written now (FILE.bag, then FILE_1.bag, ...).
  const std::string& path() const { return paths_.back(); }

 private:
  void open();
  void writeFixedTransforms(double sim_time);

  const BagSettings settings_;
  const TopicFilter filter_;
  const RecorderErrors errors_;
  BagWriter::Options options_;
  std::vector<std::string> paths_;  ///< every bag begun, the one being written last
  std::vector<std::string> closed_;  ///< the bags closed whole
  std::unique_ptr<BagWriter> writer_;
  std::vector<std::unique_ptr<RobotRecording>> robots_;  ///< in the order they were added
  bool fixed_transforms_due_ = false;  ///< /tf_static is written again after the next step
  const ConnectionHeader latched_tf_static_;
};

}  // namespace bullet_sim
