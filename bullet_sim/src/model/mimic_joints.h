// Mimic joints: what URDF's <mimic> and the mimic joint plugins ask, checked once the model is complete.
#pragma once

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/limits.h"
#include "bullet_sim/model/model.h"

namespace bullet_sim {

/// Drops, with a warning each, the couplings that cannot be simulated (a fixed follower, a leader that is no
/// moving joint, a joint that follows itself), as Gazebo loads such a robot; gives the others their strength:
/// the plugin's maxEffort, else the follower's effort limit, else max_effort (with a warning).
void resolveMimics(ModelSpec& model, const Limits& limits, Diagnostics& diagnostics);

}  // namespace bullet_sim
