// libgazebo_ros_p3d.so: the true pose and velocity of a link, as nav_msgs/Odometry in the world frame.
// Tags: bodyName (required), topicName [ground_truth], frameName [world], updateRate [0 = every step],
//   gaussianNoise [0] (on position and velocity), robotNamespace.
#pragma once

#include <string>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct GroundTruthConfig : PluginConfig {
  std::string body;  ///< <bodyName>: the child_frame_id
  // link: the link measured, body's, or the root when body names no link
  std::string topic = "ground_truth";
  std::string frame = "world";
  double noise_stddev = 0;  ///< [m], [m/s], [rad/s]
};

void parseGroundTruth(const DeclarationSource& source, GroundTruthConfig& config);

class GroundTruth : public Plugin {
 public:
  GroundTruth(const PluginDeclaration& declaration, const GroundTruthConfig& config,
              const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const Odometry& odometry() const { return odometry_.latest(); }
  uint64_t odometryCount() const { return odometry_.count(); }

 private:
  GroundTruthConfig config_;
  Stream<Odometry> odometry_;
};

}  // namespace bullet_sim
