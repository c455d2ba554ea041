// Models of a world that repeat another's contents, differing only in name and pose (a forest, a field of
// boxes, the same <include> a thousand times). libsdformat takes milliseconds and megabytes to read each
// <model> (10,000 boxes: minutes and 24 GB), so it reads one of each kind, and the copies are made from it.
#pragma once

#include <tinyxml2.h>
#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/limits.h"
#include "bullet_sim/model/world.h"

namespace bullet_sim {

struct WorldCopies {
  /// The world without the copies, every element left on its line, so that sdformat's messages point there.
  std::string reduced_text;
  struct Copy {
    std::string name;
    std::string original;                                    ///< the name of the model it repeats
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the world
    int line = 0;
  };
  std::vector<Copy> copies;  ///< in file order
};

/// The copies among the <model>s and named <include>s of the document's <world>: those whose contents, but
/// for their name and their <pose> (six numbers, no attributes), are another's; they are taken out of
/// `document`. nullopt, and `document` as it was, when there are none, or when a name repeats (sdformat then
/// reports it).
std::optional<WorldCopies> findCopies(tinyxml2::XMLDocument& document);

/// Adds each copy to `world`, after the models sdformat read: the model it repeats, renamed and placed. Poses
/// beyond limits.max_length are errors, and so are more shapes or triangles than the limits allow. The copies
/// of a model that is not loaded (an unknown include, skipped) are skipped too, with one warning naming them.
void addCopies(const WorldCopies& copies, const Limits& limits, WorldSpec& world, Diagnostics& diagnostics);

}  // namespace bullet_sim
