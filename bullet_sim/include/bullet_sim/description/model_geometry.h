// Geometry of a model at its zero pose: link frames, shape extents, inertia sanity.
#pragma once

#include <urdf_model/pose.h>
#include <Eigen/Geometry>

#include <map>
#include <optional>
#include <string>

#include "bullet_sim/description/geometry.h"

namespace bullet_sim {

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

}  // namespace bullet_sim
