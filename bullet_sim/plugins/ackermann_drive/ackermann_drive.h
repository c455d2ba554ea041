// Ackermann steering for car-like robots, declared as libgazebo_ros_ackermann_drive.so with the tag names of
// ROS 2's gazebo_plugins. Gazebo classic on ROS 1 has no such plugin: this is bullet_sim's extension, the one
// plugin block that does not work unchanged in Gazebo classic (it reports the library missing and the car
// stays where it is).
//
// cmd_vel (v, w) becomes a turn of radius R = v / w for the midpoint of the rear axle, the bicycle model's
// steering angle atan(L w / v) for wheelbase L. Each front wheel gets its own angle, tan = L / (R -/+ T / 2)
// on the inside / outside of the turn, with T the distance between the steering axes: every axle line then
// passes through the turn centre. The steering joints are held at those angles by position motors as strong
// as the joints' URDF effort limits. The rear wheels turn at the speeds an open differential settles at,
// v (R -/+ T_rear / 2) / R, by velocity motors as strong as their joints' effort limits; the front wheels
// roll freely. A turn at v = 0 cannot be driven with this steering: the wheels steer fully towards the side
// of w and the car stays put. A wheel whose axis points the other way is driven with the sign that rolls it
// forward, and that is said at load.
//
// L, T, T_rear and the wheel radius come from the URDF at the zero pose (the rear wheels' collision
// cylinders give the radius); figures in the tags that disagree are reported.
//
// Unlike ROS 2's plugin, which takes angular.z as the steering angle itself, angular.z is a turn rate
// [rad/s] as for every cmd_vel here (REP 103: +w turns counter-clockwise), and max_steer bounds the angle of
// every tyre, as its documentation says, not that of a virtual wheel between them.
//
// Its tags, ROS 2's with their defaults, their ROS 1 spellings and ours (commandTimeout, wheelModel), are the
// table ackermannTags() in ackermann_drive.cpp.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "bullet_sim/plugins/drive_support.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

/// The car's geometry as the URDF gives it at the zero pose [m].
struct AckermannGeometry {
  double wheelbase = 0;       ///< from the rear axle to the line through the steering axes
  double steering_track = 0;  ///< between the steering axes
  double rear_track = 0;      ///< between the rear wheels
  double wheel_radius = 0;    ///< of the rear wheels
  double front_track = 0;     ///< between the front wheels' joints
};

/// A joint the drive moves, as the URDF has it.
struct AckermannJoint {
  std::string name;
  double sign = 1;    ///< +1 when a positive angle steers left, or a positive velocity rolls forward
  double effort = 0;  ///< [N m] the URDF's effort limit, the motor's strength
};

/// Filled from the tag table by the parser; ackermann_joint_commander fills it from its parameters, with the
/// same defaults for max_steer and max_speed.
struct AckermannConfig : DriveConfigHead {
  std::string front_left_joint;
  std::string front_right_joint;
  std::string rear_left_joint;
  std::string rear_right_joint;
  std::string left_steering_joint;
  std::string right_steering_joint;
  double max_steer = 0.6;              ///< [rad] no tyre steers further (nor beyond its joint limits)
  double max_speed = 20;               ///< [m/s] |v| is clamped to this
  std::optional<double> wheel_base;    ///< [m] only checked against the URDF
  std::optional<double> track_width;   ///< [m] of the rear wheels; only checked
  std::optional<double> wheel_radius;  ///< [m] of the rear wheels; only checked

  // From the URDF, at load:
  AckermannGeometry geometry;
  AckermannJoint left_steering, right_steering, rear_left, rear_right, front_left, front_right;
  /// Steering limits per wheel [rad], max_steer and the joint limits combined: {right turn, left turn}.
  std::array<double, 2> left_limits{}, right_limits{};
};

/// Read and checked against the model: the joints exist and move, the steering joints turn about the vertical
/// and have effort limits, the base frame exists, the tag figures agree with the URDF.
void parseAckermann(const DeclarationSource& source, AckermannConfig& config);

/// Steering angles of the two front wheels [rad], positive to the left.
struct SteeringAngles {
  double left = 0;
  double right = 0;
};

/// The Ackermann angles for a turn of `curvature` [1/m] (1 / radius of the rear axle's midpoint, positive to
/// the left; 0 = straight): tan = L k / (1 -/+ k T / 2) for the left / right wheel, with `wheelbase` L [m]
/// and `steering_track` T [m], the distance between the steering axes.
SteeringAngles ackermannAngles(double wheelbase, double steering_track, double curvature);

/// Reads into `config` the joints its names give and the geometry they have in `model` at the zero pose, as
/// the plugin does at load (also for ackermann_joint_commander, which drives the joints through ros_control).
/// Each problem goes to `diagnostics`, after `where`.
void readAckermannGeometry(const ModelSpec& model, const std::string& where, AckermannConfig& config,
                           Diagnostics& diagnostics);

/// The curvature [1/m] at which the first tyre on the left (`side` = 1) or right (-1) reaches its limit.
double ackermannCurvatureLimit(const AckermannConfig& config, double side);

/// What the six joints are commanded for cmd_vel (`linear` [m/s], `angular` [rad/s]) within max_speed and the
/// steering limits: the steering joints' positions [rad] and the wheels' velocities [rad/s], each wheel
/// rolling at the speed of its own distance from the turn centre.
struct AckermannJointCommands {
  double curvature = 0;  ///< [1/m] steered for, after the limits
  double left_steering = 0, right_steering = 0;
  double front_left = 0, front_right = 0, rear_left = 0, rear_right = 0;
};
AckermannJointCommands ackermannJointCommands(const AckermannConfig& config, double linear, double angular);

class AckermannDrive : public DrivePlugin {
 public:
  AckermannDrive(const PluginDeclaration& declaration, const AckermannConfig& config,
                 const PluginSetup& setup);

  void applyCommands(const StepTime& time, RobotBody& body) override;
  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const AckermannConfig& config() const { return config_; }
  const AckermannGeometry& geometry() const { return config_.geometry; }
  /// The curvature [1/m] the last update steered for, after the steering limits.
  double curvature() const { return curvature_; }

 private:
  void onReset() override;

  AckermannConfig config_;
  int left_steering_ = -1, right_steering_ = -1, rear_left_ = -1, rear_right_ = -1;  ///< joint indices
  bool updated_this_step_ = false;
  double curvature_ = 0;
};

}  // namespace bullet_sim
