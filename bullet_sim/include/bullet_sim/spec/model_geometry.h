// Geometry of a URDF model at its zero pose: link frames, collision extents, inertia sanity.
#pragma once

#include <urdf_model/model.h>
#include <Eigen/Geometry>

#include <functional>
#include <map>
#include <optional>
#include <string>

#include "bullet_sim/spec/mesh.h"

namespace bullet_sim {

Eigen::Isometry3d toIsometry(const urdf::Pose& pose);

/// Pose of every link in the root link's frame, with every joint at position 0.
std::map<std::string, Eigen::Isometry3d> linkPosesAtZero(const urdf::ModelInterface& model);

/// Supplies the triangles of a URDF mesh geometry (resolving its filename); nullopt when it cannot.
using MeshSource = std::function<std::optional<TriangleMesh>(const urdf::Mesh&)>;

/// Lowest z [m] of a geometry placed at `pose`. Cylinders are URDF's: along their local z axis.
/// Returns nullopt for a mesh that `meshes` cannot supply.
std::optional<double> lowestPoint(const urdf::Geometry& geometry, const Eigen::Isometry3d& pose,
                                  const MeshSource& meshes);

/// Why an inertial is not physically valid (non-positive or non-finite mass, inertia not positive definite,
/// principal moments breaking the triangle inequality), or nullopt when it is valid.
std::optional<std::string> inertiaProblem(const urdf::Inertial& inertial);

}  // namespace bullet_sim
