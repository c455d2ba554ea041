// Values that sdformat 9, Gazebo 11's, reads and Gazebo takes, but that sdformat 12, ours, refuses: a
// negative <surface><friction><ode><mu> or <mu2> (its description's min 0, which sdformat enforces since 10)
// and a joint axis of length up to 1e-6 (JointAxis::SetXyz calls it zero). Each is rewritten in place, on
// its line, before sdformat reads the text, with a warning naming it.
#pragma once

#include <tinyxml2.h>

#include <string>
#include <vector>

namespace bullet_sim {

/// Rewrites in `text`, which `document` holds: each negative mu or mu2 of a <surface><friction><ode> as
/// SurfaceSpec::kUnlimitedMu, as Gazebo's FrictionPyramid::SetMu reads it; each <axis> or <axis2> <xyz>
/// shorter than kShortestAxis but not zero as its direction, as Gazebo's ODE normalizes it. Returns one
/// warning per value, naming it and its line (`source` names the file).
std::vector<std::string> rewriteSdf9Values(const tinyxml2::XMLDocument& document, const std::string& source,
                                           std::string& text);

}  // namespace bullet_sim
