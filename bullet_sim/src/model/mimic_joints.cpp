#include "model/mimic_joints.h"

#include <sstream>

namespace bullet_sim {

namespace {

/// Why `follower`'s coupling cannot be simulated, or "".
std::string mimicProblem(const ModelSpec& model, const JointSpec& follower) {
  const JointSpec::Mimic& mimic = *follower.mimic;
  if (!follower.moves()) return "the joint is fixed, so nothing follows";
  if (mimic.joint == follower.name) return "the joint follows itself";
  const JointSpec* leader = model.joint(mimic.joint);
  if (!leader || !leader->moves()) {
    return "[" + mimic.joint + "] is not a moving joint" + didYouMean(mimic.joint, model.jointNames());
  }
  return "";
}

}  // namespace

void resolveMimics(ModelSpec& model, const Limits& limits, Diagnostics& diagnostics) {
  for (JointSpec& follower : model.joints) {
    if (!follower.mimic) continue;
    JointSpec::Mimic& mimic = *follower.mimic;
    const std::string where = "joint [" + follower.name + "] " + mimic.source + " of [" + mimic.joint + "]: ";
    if (const std::string problem = mimicProblem(model, follower); !problem.empty()) {
      diagnostics.warning(where + problem + "; it moves on its own, as in Gazebo");
      follower.mimic.reset();
      continue;
    }
    if (mimic.max_effort > 0) continue;
    mimic.max_effort = follower.effort;
    if (mimic.max_effort > 0) continue;
    std::ostringstream message;
    message << where << "the joint has no effort limit to follow with: the coupling is as strong as "
            << limits.max_effort << " (max_effort); set <limit effort=...> to bound it";
    diagnostics.warning(message.str());
    mimic.max_effort = limits.max_effort;
  }
}

}  // namespace bullet_sim
