// How a robot model splits into rigid parts (their mass: combineInertia): shared by the wheel models.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/physics/robot_body.h"

namespace bullet_sim {

/// A robot split at its moving joints: links on fixed joints merge into their parent's part.
struct PartLayout {
  std::vector<RobotPart> parts;  ///< part 0 holds the root link; collisions in part frames
  std::vector<std::unordered_map<std::string, Eigen::Isometry3d>> link_in_part;  ///< per part: link frames
  std::vector<int> parent;              ///< parent part; -1 for part 0
  std::vector<const JointSpec*> joint;  ///< the moving joint into each part; nullptr for part 0
  std::unordered_map<std::string, int> part_of_link;
};

/// Splits `model` (which must outlive the layout: it points into its joints).
PartLayout partitionAtMovingJoints(const ModelSpec& model);

/// Reports what keeps `part`, of `mass` [kg], from moving as a body: no mass, or a plane among its
/// collisions (only static worlds may have one). Whether it may move.
bool checkMovingPart(const RobotPart& part, double mass, Diagnostics& diagnostics);

}  // namespace bullet_sim
