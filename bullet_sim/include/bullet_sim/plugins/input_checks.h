// The one check every plugin input (a topic message) and action goal passes before its plugin sees it:
// finite numbers, within kMaxCommand (request_values.h). PluginPorts applies it to every input and goal it is
// given, so no plugin sees a non-finite or absurd command, and the node warns about what was dropped.
#pragma once

#include "bullet_sim/plugins/actions.h"
#include "bullet_sim/plugins/outputs.h"

namespace bullet_sim {

/// Each throws std::invalid_argument naming the field and the value (e.g. "data[1] [nan] is not finite").
void checkInput(const Twist& twist);
void checkInput(const JointTrajectory& trajectory);
void checkInput(const Float64Command& command);
void checkInput(const Float64ArrayCommand& command);
inline void checkInput(const BoolCommand&) {}
void checkInput(const FollowJointTrajectoryAction::Goal& goal);

}  // namespace bullet_sim
