// The numbers of a URDF as written, checked before urdfdom reads them: urdfdom turns some bad ones into 0
// (1e309, -nan) or rejects them without naming them, and lets others through (a negative box, a mass of
// 1e30) that break Bullet or Embree later.
#pragma once

#include <tinyxml2.h>

#include <set>
#include <string>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/limits.h"
#include "bullet_sim/model/model.h"

namespace bullet_sim {

/// What checkUrdfValues found.
enum class UrdfValues {
  kFine,
  kRefused,  ///< a number: the model is refused, but the rest of the file can still be checked
  kTooMany,  ///< a count: too many to look at each, so nothing more is read
};

/// Checks the counts of links, moving joints and shapes against `limits`, and every number of every <link>
/// and <joint>: a number, finite, sizes positive, lengths, masses and inertias within `limits`. Each problem
/// is an error naming the element and the text as written. kTooMany when the counts are above the limits:
/// then the values are not checked, and the file is too large to read further. After a bad value, the rest of
/// the file is still read (every problem at once); the loader refuses it for the error. `bad_links`, when
/// given, receives the links with a refused number of their own: their other faults (a zero mass, a singular
/// inertia) are what urdfdom made of that number, not more faults to report.
UrdfValues checkUrdfValues(const tinyxml2::XMLElement& robot, const Limits& limits, Diagnostics& diagnostics,
                           std::set<std::string>* bad_links = nullptr);

/// The counts of links, moving joints and shapes of every <model> in an SDF text, against `limits`, before
/// libsdformat reads it (3,000 links take it about 25 s to read). An error for each count above its limit;
/// false then. A text tinyxml2 cannot parse passes: libsdformat names its fault.
bool checkSdfCounts(const std::string& sdf_text, const Limits& limits, Diagnostics& diagnostics);

/// The same bounds on a model read as numbers already (an SDF model to spawn, whose shapes and poses its
/// reader checked): the counts of links, moving joints and shapes, masses, inertias and joint values.
void checkModelValues(const ModelSpec& model, const Limits& limits, Diagnostics& diagnostics);

}  // namespace bullet_sim
