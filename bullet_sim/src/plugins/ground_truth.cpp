#include "bullet_sim/plugins/ground_truth.h"

namespace bullet_sim {

GroundTruthConfig parseGroundTruth(const DeclarationSource& source) {
  PluginTags& tags = source.tags;
  GroundTruthConfig config;
  if (!tags.has("bodyName"))
    source.diagnostics.error(tags.where() + " has no <bodyName>: name the link to follow");
  config.body = tags.frame("bodyName", source.model.root, /*gazebo_drops_slash=*/false);
  config.link = frameLink(source, "bodyName", config.body, source.model.root);
  config.topic = tags.text("topicName", config.topic);
  config.robot_namespace = tags.text("robotNamespace", "");
  config.update_rate = tags.positive("updateRate", 0, /*allow_zero=*/true);
  config.noise_stddev = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
  config.frame = tags.frame("frameName", config.frame);
  if (config.frame != "world" && config.frame != "map") {
    source.diagnostics.warning(tags.where() + " <frameName> [" + config.frame +
                               "]: poses are given in the world frame, whatever the name");
  }
  tags.accept({"alwaysOn", "xyzOffsets", "rpyOffsets"});
  return config;
}

GroundTruth::GroundTruth(const PluginDeclaration& declaration, const GroundTruthConfig& config,
                         const PluginSetup& setup)
    : Plugin(declaration, setup), config_(config) {
  Odometry& odometry = odometry_.next();
  odometry.frame_id = config_.frame;
  odometry.child_frame_id = config_.body;
  const double variance = config_.noise_stddev * config_.noise_stddev;
  for (int i : {0, 7, 14, 21, 28, 35}) odometry.pose_covariance[i] = odometry.twist_covariance[i] = variance;
  addOutput(config_.topic, odometry_);
}

void GroundTruth::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer().due(time)) return;
  Odometry& odometry = odometry_.next();
  odometry.stamp = time.sim_time;
  odometry.pose = body.linkPose(config_.link);
  odometry.pose.translation() += gaussian3(config_.noise_stddev);
  // p3d reports velocities in the world frame.
  odometry.linear_velocity = body.linkLinearVelocity(config_.link) + gaussian3(config_.noise_stddev);
  odometry.angular_velocity = body.linkAngularVelocity(config_.link) + gaussian3(config_.noise_stddev);
  odometry_.publish();
}

}  // namespace bullet_sim
