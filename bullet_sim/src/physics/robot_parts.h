// How a robot model splits into rigid parts, and the mass of a set of links: shared by the wheel models.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "bullet_sim/description/model_spec.h"
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

/// Mass [kg], centre of mass [m] and inertia about it [kg m^2] of links, each placed by its frame.
struct MassProperties {
  double mass = 0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();

  /// A frame at the centre of mass along the principal axes (right-handed); `moments` gets the principal
  /// moments about those axes.
  Eigen::Isometry3d principalFrame(Eigen::Vector3d* moments) const;
};

MassProperties combineInertia(const ModelSpec& model,
                              const std::vector<std::pair<std::string, Eigen::Isometry3d>>& placed_links);

}  // namespace bullet_sim
