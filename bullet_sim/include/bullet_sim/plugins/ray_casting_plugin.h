// A plugin whose readings are rays cast from the link its sensor sits on (lidars, rangers): it aims them from
// the stepped body and casts them beside other robots' or behind physics (plugin.h's phases 3a and 3b); its
// sense() asks readingDue() and publishes ranges().
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/plugins/sensor_interfaces.h"

namespace bullet_sim {

/// A ray sensor's rays: where they start and go, and how far.
struct RayAim {
  std::string link;                                        ///< the link the sensor sits on
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the sensor in its link's frame
  std::vector<Eigen::Vector3f> directions;                 ///< unit, in the sensor frame
  double range_max = 0;                                    ///< [m]
};

class RayCastingPlugin : public Plugin, public RaySensor {
 public:
  RayCastingPlugin(const PluginDeclaration& declaration, const PluginSetup& setup, RayAim aim);

  bool castsRays(const StepTime& time) const override { return timer().wouldFire(time); }
  void aimRays(const StepTime& time, const RobotBody& body) override;
  void castRays(const RayCaster& rays) override;
  RayPattern rayPattern(const RobotBody& body) const override;

 protected:
  /// For sense(): whether a reading is due at `time` (its timer then schedules the next); if so, its rays are
  /// cast, here when the caller skipped aimRays() and castRays().
  bool readingDue(const StepTime& time, const RobotBody& body, const RayCaster& rays);
  /// in the world, where they were aimed from
  const Eigen::Isometry3d& sensorPose() const { return sensor_; }
  const std::vector<Eigen::Vector3f>& directions() const { return aim_.directions; }  ///< in the sensor frame
  const std::vector<double>& ranges() const { return ranges_; }  ///< [m] per ray; +inf: no hit within range

 private:
  RayAim aim_;
  BodyId own_body_;  ///< skipped by its rays
  Eigen::Isometry3d sensor_ = Eigen::Isometry3d::Identity();
  double aimed_at_ = -1;  ///< [s] the sim time it aimed for
  std::vector<Eigen::Vector3f> world_directions_;
  std::vector<double> ranges_;
};

}  // namespace bullet_sim
