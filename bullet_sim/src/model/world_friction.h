// A negative <surface><friction><ode><mu> or <mu2>: sdformat 9, Gazebo 11's, reads it and Gazebo takes it for
// unlimited friction; sdformat 12, ours, refuses it (its <mu> has min 0). It is rewritten before sdformat
// reads the file.
#pragma once

#include <tinyxml2.h>

#include <string>
#include <vector>

namespace bullet_sim {

/// Rewrites in `text`, which `document` holds, each negative <mu> or <mu2> of a <surface><friction><ode> as
/// SurfaceSpec::kUnlimitedMu, in place on its line. Returns one warning per value, naming it and its line
/// (`source` names the file).
std::vector<std::string> unlimitNegativeMu(const tinyxml2::XMLDocument& document, const std::string& source,
                                           std::string& text);

}  // namespace bullet_sim
