#include "bullet_sim/plugins/drive_support.h"

#include <cmath>

namespace bullet_sim {

bool VelocityCommand::set(double linear, double angular, double sim_time) {
  if (!std::isfinite(linear) || !std::isfinite(angular)) return false;
  linear_ = linear;
  angular_ = angular;
  command_time_ = sim_time;
  return true;
}

void setGroundTruth(Odometry& odometry, const RobotBody& body, const std::string& base_frame, double stamp) {
  const Eigen::Isometry3d base = body.linkPose(base_frame);
  const Eigen::Matrix3d to_base = base.linear().transpose();
  odometry.stamp = stamp;
  odometry.pose = base;
  odometry.linear_velocity = to_base * body.linkLinearVelocity(base_frame);
  odometry.angular_velocity = to_base * body.linkAngularVelocity(base_frame);
}

}  // namespace bullet_sim
