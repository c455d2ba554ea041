// The strike matrix (issue 28): robots driven into a flat wall, the edge of a door frame and a thin panel, at
// several speeds, angles, wheel models and step sizes, each run judged against bounds computed from the
// robot's own mass, inertia and geometry (never against an earlier run). `bench --strikes` runs it whole;
// the contact tests run cells of it. ROS-free.
#pragma once

#include <Eigen/Geometry>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "bullet_sim/model/world.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

/// What a robot is driven into: a wall 0.1 m thick, the vertical end of a door frame's post (0.1 m thick,
/// the robot's nearer quarter meeting it), or a panel 0.02 m thick. Static, mu = 1 (Gazebo's default).
enum class StrikeTarget { kWall, kDoorEdge, kPanel };

std::string targetName(StrikeTarget target);

/// A robot as the matrix drives it: through its drive plugin, or through ros_control's diff_drive_controller
/// when `control_yaml` holds its controllers (each one there is loaded and started).
struct StrikeRobot {
  std::string name;          ///< for reports
  std::string urdf;          ///< expanded
  std::string control_yaml;  ///< ros_control's parameters, on the parameter server's root; "" for none
};

/// One cell of the matrix.
struct StrikeCell {
  std::string wheel_model = "raycast";  ///< "contact" or "raycast"
  double step = 0.001;                  ///< [s] the world's step
  double speed = 0.5;                   ///< [m/s] commanded
  double angle = 0;                     ///< [rad] between the robot's heading and the target's normal
  StrikeTarget target = StrikeTarget::kWall;
  /// With the motors off (the drive's torque 1e-9 N m: plugins refuse 0), set_model_state gives the robot
  /// the speed 0.3 m before the target and it coasts in; the run then watches its energy.
  bool coast = false;
};

std::string cellName(const StrikeRobot& robot, const StrikeCell& cell);

/// The two tipping bounds of a strike (issue 28), from the robot settled on the ground, heading into the
/// target along n (the target's normal, horizontal), with g = 9.81 m/s^2:
/// - impact: the strike at v_n = v cos(angle) puts angular momentum m v_n (h - z_c) about the point struck;
///   about the support edge it turns over (the front one when the contact is below the centre of mass, the
///   rear one when above), omega0 = m v_n (h - z_c) / I_p, whose energy 1/2 I_p omega0^2 tips the robot over
///   when it exceeds the barrier m g (sqrt(d^2 + h^2) - h), d the centre of mass's distance to that edge;
/// - stall: held at the target, the driven wheels push with F = min(mu m g, sum tau_max / r) cos(angle) at
///   the ground against the target's reaction at z_c: the couple F z_c lifts the front over the rear edge
///   when it exceeds m g d_rear. Only a robot whose driven wheels are on that rear edge can keep pushing as
///   the front lifts; with its drive wheels ahead of a rear caster, the lifting front unloads them.
/// A robot tips only if, held at the target by its struck point, it can turn about that edge until its centre
/// of mass passes over it before another of its points meets the target or the ground (roomToTip): a robot
/// whose base reaches the wall as it leans back leans on the wall.
/// Climbing: a driven wheel meets the target first, and mu times its share of the push the driven wheels'
/// load allows is at least that wheel's load, so the wall's friction on the spinning wheel can carry it up.
/// Within 20 % of that threshold, neither the climb nor the tilt limits are asserted.
struct StrikeBounds {
  double mass = 0;           ///< [kg]
  double com_height = 0;     ///< h [m] above the ground
  double contact_height = 0;  ///< z_c [m]: where the robot first meets the target
  /// d [m]: from the centre of mass to the front and rear support edges, along n
  double front = 0, rear = 0;
  double pitch_inertia = 0;  ///< I_p [kg m^2] about the edge the impact turns the robot over
  double impact_energy = 0;  ///< [J]
  double barrier = 0;        ///< [J]
  double tip_speed = std::numeric_limits<double>::infinity();  ///< [m/s] at which the impact bound tips it
  double push = 0;           ///< F [N]
  double wheel_load = 0;     ///< [N] on the driven wheel that meets the target first (0: none does)
  bool wheel_first = false;  ///< a driven wheel meets the target first
  bool rear_driven = false;  ///< the rear support edge is driven wheels
  bool impact_tips = false;
  bool stall_tips = false;
  double climb_ratio = 0;  ///< the wall's friction on the struck driven wheel over its load (0: none struck)
  bool tips() const { return impact_tips || stall_tips; }
  bool climbs() const { return climb_ratio >= 1.2; }  ///< climbing is physical
  bool mayClimb() const { return climb_ratio > 0.8 && climb_ratio < 1.2; }  ///< too close to tell
};

/// Where the robot's root link was at one moment of a run.
struct StrikeTrailPoint {
  double time = 0;  ///< [s] since the approach began
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< [m] world
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();       ///< [rad] roll, pitch, yaw (world axes)
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();    ///< [m/s]
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();   ///< [rad/s]
  double tilt = 0;  ///< [rad] from its settled attitude
};

/// What happened in one run, and the rules it broke.
struct StrikeOutcome {
  StrikeBounds bounds;
  bool reached = false;       ///< the robot met the target
  bool given_speed = false;   ///< set_model_state gave it the speed 0.5 m before the target
  double max_tilt = 0;        ///< [rad] from its settled attitude, the run's largest
  double rise = 0;            ///< [m] its lowest point's largest height above the ground (a leap)
  double root_rise = 0;       ///< [m] its root link's largest height above its settled height
  double penetration = 0;     ///< [m] deepest of its points inside the target
  bool through = false;       ///< a part passed through the target (or its root reached into it)
  double path = 0;            ///< [m] the root link's, sampled every 50 ms
  double command_path = 0;    ///< [m] the integral of the command as the drive ramps it
  double energy_gain = 0;     ///< [J] coasting: the largest rise of the energy above its start
  double energy_allowance = 0;  ///< [J] coasting: 1/2 M (0.1 m/s)^2 + 1 % of the start
  double sim_seconds = 0;     ///< [s] of sim time
  double wall_seconds = 0;    ///< [s] the run took
  std::vector<StrikeTrailPoint> trail;  ///< the root link every 50 ms (the path's samples)
  std::vector<std::string> failures;  ///< each rule broken, in words; empty when the cell passes
  bool passed() const { return failures.empty(); }
};

/// Called 0.3 s after the first contact ("contact") and at the end ("end") of a run, to draw it.
using StrikeSnapshot =
    std::function<void(const Simulation& simulation, const std::string& robot, const std::string& moment)>;

/// Runs one cell in `world` (usually empty.world; the target is added to it). A robot that tips over
/// reaching its speed runs again, given the speed by set_model_state 0.5 m before the target. Throws
/// SpecError when the robot cannot be loaded.
StrikeOutcome runStrike(const StrikeRobot& robot, const StrikeCell& cell, const WorldSpec& world,
                        const StrikeSnapshot& snapshot = {});

/// [J] Sum over the robot's links of 1/2 m v^2 + 1/2 w^T I w + m g z (z of each link's centre of mass above
/// the world's origin), plus what its wheel model's springs hold.
double robotEnergy(const Robot& robot, const Eigen::Vector3d& gravity);

/// [kg] the robot's mass, its links' summed.
double robotMass(const ModelSpec& model);

/// `urdf` with every drive plugin's (and ros_control's) <wheelModel> set; text that is not XML is returned.
std::string withStrikeWheelModel(const std::string& urdf, const std::string& wheel_model);

/// `urdf` with its drive's motors off, at 1e-9 N m: the diff drive's and skid steer's torque tags, and the
/// effort limit of the wheels that drive it (its drive plugin's traction, or the left and right wheels of the
/// diff_drive_controllers in `control_yaml`), where the Ackermann drive and ros_control take their torque.
std::string withMotorsOff(const std::string& urdf, const std::string& control_yaml = "");

}  // namespace bullet_sim
