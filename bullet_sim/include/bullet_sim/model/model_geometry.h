// Geometry of a model at its zero pose: link frames, shape extents, inertia sanity.
#pragma once

#include <urdf_model/pose.h>
#include <Eigen/Geometry>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "bullet_sim/model/geometry.h"

namespace bullet_sim {

class Diagnostics;
struct ModelSpec;

Eigen::Isometry3d toIsometry(const urdf::Pose& pose);

/// Pose of every link in the root link's frame, with every joint at position 0.
std::map<std::string, Eigen::Isometry3d> linkPosesAtZero(const ModelSpec& model);

/// Lowest z [m] of a shape placed at `pose`; -infinity for a plane that is not horizontal.
double lowestPoint(const Shape& shape, const Eigen::Isometry3d& pose);

/// Axis-aligned bounding box [m] of a shape placed at `pose`; empty for a plane or a mesh that is not loaded.
Eigen::AlignedBox3d boundingBox(const Shape& shape, const Eigen::Isometry3d& pose);

/// Why a mass [kg] and an inertia tensor about the centre of mass [kg m^2] are not physically valid
/// (non-positive mass, not positive definite, principal moments breaking I1 + I2 >= I3), or nullopt.
std::optional<std::string> inertiaProblem(double mass, const Eigen::Matrix3d& inertia);

/// Mass [kg], centre of mass [m] and inertia about it [kg m^2] of links, each placed by its frame.
struct MassProperties {
  double mass = 0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();

  /// A frame at the centre of mass along the principal axes (right-handed); `moments` gets the principal
  /// moments about those axes.
  Eigen::Isometry3d principalFrame(Eigen::Vector3d* moments) const;
};

/// Gazebo lumps links so (fixed-joint lumping): masses summed, centres of mass combined, inertias by the
/// parallel-axis theorem. Links without <inertial> add nothing.
MassProperties combineInertia(const ModelSpec& model,
                              const std::vector<std::pair<std::string, Eigen::Isometry3d>>& placed_links);

/// The bodies the simulation makes of `model`: each moving link (and the root) with the links fixed to it,
/// in the group's first link's frame. The root's body comes first.
std::vector<std::vector<std::pair<std::string, Eigen::Isometry3d>>> rigidBodies(const ModelSpec& model);

/// A negative mass is an error. Then lumps each body's links as Gazebo does (combineInertia); a body whose
/// lumped mass or inertia is not physically valid (zero mass, inertia zero or not positive definite) gets,
/// after one warning naming its first link and the value, a solid box's: its mass (when there is none, 1% of
/// the robot's, at least 0.01 kg) filling its collisions' bounding box. A static model, and the root of one
/// fixed to the world (a root link named world), need none; nor a body holding a link of negative mass or one
/// of `refused_links`, whose numbers were refused already (what urdfdom made of them is no further fault).
void repairBodyInertias(ModelSpec& model, Diagnostics& diagnostics,
                        const std::set<std::string>& refused_links = {});

}  // namespace bullet_sim
