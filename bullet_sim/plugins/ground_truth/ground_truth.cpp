#include "plugins/ground_truth/ground_truth.h"

#include "bullet_sim/plugins/registry.h"

namespace bullet_sim {

void parseGroundTruth(const DeclarationSource& source, GroundTruthConfig& config) {
  PluginTags& tags = source.tags;
  if (!tags.has("bodyName"))
    source.diagnostics.error(tags.where() + " has no <bodyName>: name the link to follow");
  config.body = tags.frame("bodyName", source.model.root, /*gazebo_drops_slash=*/false);
  config.link = frameLink(source, "bodyName", config.body, source.model.root);
  config.topic = tags.text("topicName", config.topic);
  config.noise_stddev = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
  config.frame = tags.frame("frameName", config.frame);
  if (config.frame != "world" && config.frame != "map") {
    source.diagnostics.warning(tags.where() + " <frameName> [" + config.frame +
                               "]: poses are given in the world frame, whatever the name");
  }
  tags.accept({"alwaysOn", "xyzOffsets", "rpyOffsets"});
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

BULLET_SIM_PLUGIN_FOLDER(ground_truth) {
  PluginType type = pluginType<GroundTruth>("libgazebo_ros_p3d.so", parseGroundTruth, {});
  type.rate = {RateRule::From::kTags, {"updateRate"}, 0};
  type.tf_prefix = TfPrefixRule::kNamespaceParam;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
