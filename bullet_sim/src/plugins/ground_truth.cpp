#include "bullet_sim/plugins/ground_truth.h"

namespace bullet_sim {

GroundTruth::GroundTruth(const PluginSpec& spec, const ModelSpec& model, Diagnostics& diagnostics,
                         uint64_t seed)
    : Plugin(spec.name), seed_(seed), noise_(seed) {
  PluginTags tags(spec.element, "plugin [" + spec.name + "]", diagnostics);
  body_ = tags.text("bodyName", "");
  if (!model.link(body_)) {
    diagnostics.error(tags.where() + " <bodyName> [" + body_ + "] is not a link" +
                      didYouMean(body_, model.linkNames()));
  }
  topic_ = tags.text("topicName", topic_);
  robot_namespace_ = tags.text("robotNamespace", "");
  timer_ = UpdateTimer(tags.positive("updateRate", 0, /*allow_zero=*/true));
  noise_stddev_ = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
  odometry_.frame_id = tags.text("frameName", "world");
  if (odometry_.frame_id != "world" && odometry_.frame_id != "map" && odometry_.frame_id != "/world") {
    diagnostics.warning(tags.where() + " <frameName> [" + odometry_.frame_id +
                        "]: poses are given in the world frame, whatever the name");
  }
  odometry_.child_frame_id = body_;
  tags.accept({"alwaysOn", "xyzOffsets", "rpyOffsets"});
  tags.finish();
  const double variance = noise_stddev_ * noise_stddev_;
  for (int i : {0, 7, 14, 21, 28, 35})
    odometry_.pose_covariance[i] = odometry_.twist_covariance[i] = variance;
}

void GroundTruth::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer_.due(time)) return;
  std::normal_distribution<double> gaussian(0.0, noise_stddev_);
  const auto noise = [&] {
    return noise_stddev_ > 0 ? Eigen::Vector3d(gaussian(noise_), gaussian(noise_), gaussian(noise_))
                             : Eigen::Vector3d::Zero();
  };
  odometry_.stamp = time.sim_time;
  odometry_.pose = body.linkPose(body_);
  odometry_.pose.translation() += noise();
  // p3d reports velocities in the world frame.
  odometry_.linear_velocity = body.linkLinearVelocity(body_) + noise();
  odometry_.angular_velocity = body.linkAngularVelocity(body_) + noise();
  ++odometry_count_;
}

void GroundTruth::reset() {
  timer_.reset();
  noise_.seed(seed_);
}

}  // namespace bullet_sim
