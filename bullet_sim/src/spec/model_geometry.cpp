#include "bullet_sim/spec/model_geometry.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace bullet_sim {

Eigen::Isometry3d toIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translate(Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z));
  result.rotate(Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z));
  return result;
}

std::map<std::string, Eigen::Isometry3d> linkPosesAtZero(const urdf::ModelInterface& model) {
  std::map<std::string, Eigen::Isometry3d> poses;
  std::function<void(const urdf::Link&, const Eigen::Isometry3d&)> visit =
      [&](const urdf::Link& link, const Eigen::Isometry3d& pose) {
        poses[link.name] = pose;
        for (const auto& joint : link.child_joints) {
          const auto child = model.getLink(joint->child_link_name);
          if (child) visit(*child, pose * toIsometry(joint->parent_to_joint_origin_transform));
        }
      };
  if (const auto root = model.getRoot()) visit(*root, Eigen::Isometry3d::Identity());
  return poses;
}

std::optional<double> lowestPoint(const urdf::Geometry& geometry, const Eigen::Isometry3d& pose,
                                  const MeshSource& meshes) {
  const Eigen::Vector3d centre = pose.translation();
  const Eigen::Matrix3d rotation = pose.linear();
  switch (geometry.type) {
    case urdf::Geometry::SPHERE:
      return centre.z() - static_cast<const urdf::Sphere&>(geometry).radius;
    case urdf::Geometry::BOX: {
      const auto& dim = static_cast<const urdf::Box&>(geometry).dim;
      const Eigen::Vector3d half(dim.x / 2, dim.y / 2, dim.z / 2);
      // Support of a box along -z: sum of |z component of each half axis|.
      return centre.z() - rotation.row(2).cwiseAbs().dot(half);
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      const double axis_z = std::abs(rotation(2, 2));
      const double disc_drop = cylinder.radius * std::sqrt(std::max(0.0, 1.0 - axis_z * axis_z));
      return centre.z() - disc_drop - cylinder.length / 2 * axis_z;
    }
    case urdf::Geometry::MESH: {
      const auto mesh = meshes(static_cast<const urdf::Mesh&>(geometry));
      if (!mesh) return std::nullopt;
      double lowest = std::numeric_limits<double>::infinity();
      for (const auto& v : mesh->vertices) lowest = std::min(lowest, (pose * v).z());
      return lowest;
    }
  }
  return std::nullopt;
}

std::optional<std::string> inertiaProblem(const urdf::Inertial& inertial) {
  std::ostringstream why;
  if (!std::isfinite(inertial.mass) || inertial.mass <= 0) {
    why << "mass " << inertial.mass << " kg is not positive";
    return why.str();
  }
  Eigen::Matrix3d inertia;
  inertia << inertial.ixx, inertial.ixy, inertial.ixz,  //
      inertial.ixy, inertial.iyy, inertial.iyz,         //
      inertial.ixz, inertial.iyz, inertial.izz;
  if (!inertia.allFinite()) return std::string("inertia has a non-finite entry");
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia).eigenvalues();
  if (moments.minCoeff() <= 0) {
    why << "inertia is not positive definite (principal moments " << moments.transpose() << " kg m^2)";
    return why.str();
  }
  // Principal moments of a real body satisfy I1 + I2 >= I3; allow rounding in exported figures.
  const double tolerance = 1e-6 * moments.maxCoeff();
  if (moments(0) + moments(1) < moments(2) - tolerance) {
    why << "principal moments " << moments.transpose()
        << " kg m^2 break the triangle inequality (I1 + I2 >= I3)";
    return why.str();
  }
  return std::nullopt;
}

}  // namespace bullet_sim
