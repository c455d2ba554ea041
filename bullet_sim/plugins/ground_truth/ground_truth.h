// libgazebo_ros_p3d.so: the true pose and velocity of a link, as nav_msgs/Odometry in the world frame. Its
// tags are kGroundTruthTags in ground_truth.cpp.
#pragma once

#include <string>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct GroundTruthConfig : PluginConfig {
  std::string body;  ///< <bodyName>: the child_frame_id
  // link: the link measured, body's, or the root when body names no link
  std::string topic;
  std::string frame;
  double noise_stddev = 0;  ///< [m], [m/s], [rad/s]
};

void parseGroundTruth(const DeclarationSource& source, GroundTruthConfig& config);

class GroundTruth : public Plugin {
 public:
  GroundTruth(const PluginDeclaration& declaration, const GroundTruthConfig& config,
              const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

 private:
  GroundTruthConfig config_;
  Stream<Odometry> odometry_;
};

}  // namespace bullet_sim
