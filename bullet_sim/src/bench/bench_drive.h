// What bench's drives share: the drive axle's pose, the unicycle it is measured against, a robot's cmd_vel,
// and the timing helpers.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

using Clock = std::chrono::steady_clock;

constexpr double kSettleTime = 0.5;     ///< [s] at rest after the spawn, before driving
constexpr double kCommandPeriod = 0.1;  ///< [s] the command is re-sent as `rostopic pub -r 10` does

double secondsSince(Clock::time_point start);

/// CPU time of the calling thread [s]: what its work cost, whatever other processes took of the machine.
double threadCpuSeconds();

/// CPU time of the whole process, every thread's [s].
double processCpuSeconds();

/// The median; NAN for none.
double median(std::vector<double> values);

struct Planar {
  double x = 0, y = 0, yaw = 0;  ///< [m], [m], [rad]
};

/// A robot's wheeled drive: the wheels its plugin type says it drives, and its cmd_vel.
struct Drive {
  DrivenJoints joints;
  const InputHandler<Twist>* command = nullptr;
};

/// The robot's first drive plugin that drives wheels and takes a Twist; a Failure naming `source` when it has
/// none.
Drive driveOf(const Robot& robot, const std::string& source);

/// Where the drive axle is, as a unicycle sees it: the midpoint of the drive plugin's wheels on the ground,
/// heading along the base frame's x axis. A diff-drive robot turns about this point, not about its base
/// frame.
Planar axlePose(const Robot& robot, const DrivenJoints& drive);

/// The unicycle driven at exactly v [m/s] and w [rad/s] for `seconds` from `start`.
Planar unicycle(const Planar& start, double v, double w, double seconds);

}  // namespace bullet_sim
