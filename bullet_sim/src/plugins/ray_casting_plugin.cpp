#include "bullet_sim/plugins/ray_casting_plugin.h"

#include <utility>

namespace bullet_sim {

RayCastingPlugin::RayCastingPlugin(const PluginDeclaration& declaration, const PluginSetup& setup, RayAim aim)
    : Plugin(declaration, setup),
      aim_(std::move(aim)),
      own_body_(setup.own_ray_body),
      world_directions_(aim_.directions.size()),
      ranges_(aim_.directions.size()) {}

void RayCastingPlugin::aimRays(const StepTime& time, const RobotBody& body) {
  sensor_ = body.linkPose(aim_.link) * aim_.pose;
  aimed_at_ = time.sim_time;
}

void RayCastingPlugin::castRays(const RayCaster& rays) {
  const Eigen::Matrix3f rotation = sensor_.linear().cast<float>();
  for (size_t i = 0; i < aim_.directions.size(); ++i) world_directions_[i] = rotation * aim_.directions[i];
  rays.cast(sensor_.translation(), world_directions_, aim_.range_max, own_body_, ranges_);
}

RayPattern RayCastingPlugin::rayPattern(const RobotBody& body) const {
  RayPattern pattern{aim_.link, body.linkPose(aim_.link) * aim_.pose, {}, aim_.range_max, updateRate()};
  const Eigen::Matrix3f rotation = pattern.sensor.linear().cast<float>();
  for (const Eigen::Vector3f& direction : aim_.directions) pattern.directions.push_back(rotation * direction);
  return pattern;
}

bool RayCastingPlugin::readingDue(const StepTime& time, const RobotBody& body, const RayCaster& rays) {
  if (!timer().due(time)) return false;
  if (aimed_at_ != time.sim_time) {  // a caller that skipped phases 3a and 3b
    aimRays(time, body);
    castRays(rays);
  }
  return true;
}

}  // namespace bullet_sim
