// libgazebo_ros_p3d.so: the true pose and velocity of a link, as nav_msgs/Odometry in the world frame.
// Tags: bodyName (required), topicName [ground_truth], frameName [world], updateRate [0 = every step],
//   gaussianNoise [0] (on position and velocity), robotNamespace.
#pragma once

#include <random>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

class GroundTruth : public Plugin {
 public:
  GroundTruth(const PluginSpec& spec, const ModelSpec& model, Diagnostics& diagnostics, uint64_t seed);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;
  void reset() override;

  const std::string& topic() const { return topic_; }
  const std::string& robotNamespace() const { return robot_namespace_; }
  const Odometry& odometry() const { return odometry_; }
  uint64_t odometryCount() const { return odometry_count_; }

 private:
  std::string body_;
  std::string topic_ = "ground_truth";
  std::string robot_namespace_;
  double noise_stddev_ = 0;
  uint64_t seed_;
  UpdateTimer timer_{0};
  std::mt19937_64 noise_;
  Odometry odometry_;
  uint64_t odometry_count_ = 0;
};

}  // namespace bullet_sim
