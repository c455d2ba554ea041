#include "plugins/ground_truth/ground_truth.h"

#include "bullet_sim/plugins/gazebo_plugin_rows.h"
#include "bullet_sim/plugins/registry.h"

namespace bullet_sim {

namespace {

const TagTable kGroundTruthTags = withUnreadTutorialTags({
    {"bodyName", TagType::kFrame, "", "",
     "the link measured, and the child_frame_id; required: the plugin does not load without it",
     "an error when absent; a name that is no link is a warning, the root link is measured, and the name is "
     "still the child_frame_id"},
    {"topicName", TagType::kTopic, "ground_truth", "",
     "the topic of the odometry; required: the plugin does not load without it", "ground_truth when absent"},
    {"frameName", TagType::kFrame, "world", "",
     "the frame of the pose: world (or map), or a link of the robot that pose and velocities are relative to",
     "poses are in the world frame whatever it names (a warning unless world or map); it is the frame_id"},
    {"updateRate", TagType::kRate, "0", "Hz", "how often it publishes; 0: every step", ""},
    {"gaussianNoise", TagType::kDeviation, "0", "",
     "the standard deviation of a zero-mean noise on the position [m] and the velocities [m/s, rad/s]",
     "the same, and the covariances' diagonals are its square"},
});

}  // namespace

void parseGroundTruth(const DeclarationSource& source, GroundTruthConfig& config) {
  PluginTags& tags = source.tags;
  if (!tags.has("bodyName"))
    source.diagnostics.error(tags.where() + " has no <bodyName>: name the link to follow");
  config.body = tags.frame("bodyName", source.model.root, /*gazebo_drops_slash=*/false);
  config.link = frameLink(source, "bodyName", config.body, source.model.root);
  config.topic = tags.text("topicName");
  config.noise_stddev = tags.deviation("gaussianNoise");
  config.frame = tags.frame("frameName", kGroundTruthTags.row("frameName")->fallback);
  if (config.frame != "world" && config.frame != "map") {
    source.diagnostics.warning(tags.where() + " <frameName> [" + config.frame +
                               "]: poses are given in the world frame, whatever the name");
  }
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
  PluginType type = pluginType<GroundTruth>("libgazebo_ros_p3d.so", parseGroundTruth, kGroundTruthTags);
  type.rate = {RateRule::From::kTags, {"updateRate"}, 0};
  type.tf_prefix = TfPrefixRule::kNamespaceParam;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
