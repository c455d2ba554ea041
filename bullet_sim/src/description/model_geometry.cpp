#include "bullet_sim/description/model_geometry.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "bullet_sim/description/model_spec.h"

namespace bullet_sim {

Eigen::Isometry3d toIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translate(Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z));
  result.rotate(Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z));
  return result;
}

std::map<std::string, Eigen::Isometry3d> linkPosesAtZero(const ModelSpec& model) {
  std::map<std::string, Eigen::Isometry3d> poses;
  poses[model.root] = Eigen::Isometry3d::Identity();
  for (const auto& joint : model.joints)
    poses[joint.child] = poses.at(joint.parent) * joint.origin;  // parents first
  return poses;
}

double lowestPoint(const Shape& shape, const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d centre = pose.translation();
  const Eigen::Matrix3d rotation = pose.linear();
  switch (shape.type) {
    case Shape::Type::kSphere:
      return centre.z() - shape.radius;
    case Shape::Type::kBox:
      // Support of a box along -z: the sum of the z extents of its half axes.
      return centre.z() - rotation.row(2).cwiseAbs().dot(shape.box_size / 2);
    case Shape::Type::kCylinder: {
      const double axis_z = std::abs(rotation(2, 2));
      const double disc_drop = shape.radius * std::sqrt(std::max(0.0, 1.0 - axis_z * axis_z));
      return centre.z() - disc_drop - shape.length / 2 * axis_z;
    }
    case Shape::Type::kMesh: {
      double lowest = std::numeric_limits<double>::infinity();
      if (shape.mesh) {
        for (const auto& v : shape.mesh->vertices) lowest = std::min(lowest, (pose * v).z());
      }
      return lowest;
    }
    case Shape::Type::kPlane: {
      const Eigen::Vector3d normal = rotation * shape.plane_normal;
      return normal.head<2>().norm() < 1e-12 ? centre.z() : -std::numeric_limits<double>::infinity();
    }
  }
  return std::numeric_limits<double>::infinity();
}

Eigen::AlignedBox3d boundingBox(const Shape& shape, const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d rotation = pose.linear();
  Eigen::Vector3d half = Eigen::Vector3d::Zero();  // half extents along the world axes
  switch (shape.type) {
    case Shape::Type::kBox:
      half = rotation.cwiseAbs() * (shape.box_size / 2);
      break;
    case Shape::Type::kCylinder:
      for (int i = 0; i < 3; ++i) {
        const double axis = std::abs(rotation(i, 2));
        half(i) = shape.length / 2 * axis + shape.radius * std::sqrt(std::max(0.0, 1.0 - axis * axis));
      }
      break;
    case Shape::Type::kSphere:
      half.setConstant(shape.radius);
      break;
    case Shape::Type::kMesh: {
      Eigen::AlignedBox3d box;
      if (shape.mesh) {
        for (const auto& v : shape.mesh->vertices) box.extend(pose * v);
      }
      return box;
    }
    case Shape::Type::kPlane:
      return Eigen::AlignedBox3d();
  }
  return Eigen::AlignedBox3d(pose.translation() - half, pose.translation() + half);
}

std::optional<std::string> inertiaProblem(double mass, const Eigen::Matrix3d& inertia) {
  std::ostringstream why;
  if (!std::isfinite(mass) || mass <= 0) {
    why << "mass " << mass << " kg is not positive";
    return why.str();
  }
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
