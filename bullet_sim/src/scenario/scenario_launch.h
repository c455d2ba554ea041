// A launch scenario: a ROS master on a free port, the simulator (scenario_host, which records and judges the
// run) and the user's launch file, all started through one roslaunch and all stopped within a bounded time.
#pragma once

#include <string>

#include "bullet_sim/scenario/scenario_command.h"

namespace bullet_sim {

/// Runs `spec` (which has a launch) into `out` and returns its verdict, read from the result.json that the
/// simulator writes. Throws std::runtime_error when it cannot start, or when the simulator wrote no result
/// (the message points at out/launch.log). No process it started is left running when it returns.
Verdict runLaunch(const ScenarioSpec& spec, const ScenarioCommand& command, const std::string& out);

}  // namespace bullet_sim
