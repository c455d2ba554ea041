#include "bullet_sim/model/model_geometry.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model.h"

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

Eigen::Isometry3d MassProperties::principalFrame(Eigen::Vector3d* moments) const {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> principal(inertia);
  Eigen::Matrix3d axes = principal.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  *moments = principal.eigenvalues();
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.translate(com);
  frame.rotate(axes);
  return frame;
}

MassProperties combineInertia(const ModelSpec& model,
                              const std::vector<std::pair<std::string, Eigen::Isometry3d>>& placed_links) {
  MassProperties total;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& [name, frame] : placed_links) {
    const LinkSpec& link = *model.link(name);
    if (!link.inertial) continue;
    total.mass += link.inertial->mass;
    moment += link.inertial->mass * (frame * link.inertial->com);
  }
  if (total.mass <= 0) return total;
  total.com = moment / total.mass;
  for (const auto& [name, frame] : placed_links) {
    const LinkSpec& link = *model.link(name);
    if (!link.inertial) continue;
    // Parallel axis theorem about the common centre of mass.
    const Eigen::Vector3d d = frame * link.inertial->com - total.com;
    total.inertia +=
        frame.linear() * link.inertial->inertia * frame.linear().transpose() +
        link.inertial->mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  return total;
}

std::vector<std::vector<std::pair<std::string, Eigen::Isometry3d>>> rigidBodies(const ModelSpec& model) {
  std::vector<std::vector<std::pair<std::string, Eigen::Isometry3d>>> bodies{
      {{model.root, Eigen::Isometry3d::Identity()}}};
  std::map<std::string, std::pair<size_t, Eigen::Isometry3d>> placed{
      {model.root, {0, Eigen::Isometry3d::Identity()}}};
  for (const auto& joint : model.joints) {  // parents first
    auto [body, frame] = placed.at(joint.parent);
    if (joint.moves()) {
      body = bodies.size();
      frame = Eigen::Isometry3d::Identity();
      bodies.emplace_back();
    } else {
      frame = frame * joint.origin;
    }
    bodies[body].emplace_back(joint.child, frame);
    placed[joint.child] = {body, frame};
  }
  return bodies;
}

namespace {

/// A solid box of `mass` [kg] filling the bounding box of `body`'s collisions (0.1 m across without any; no
/// side below 1 cm), centred on `com` when given.
MassProperties boxBody(const ModelSpec& model,
                       const std::vector<std::pair<std::string, Eigen::Isometry3d>>& body, double mass,
                       const std::optional<Eigen::Vector3d>& com) {
  Eigen::AlignedBox3d box;
  for (const auto& [name, frame] : body) {
    for (const Collision& collision : model.link(name)->collisions)
      box.extend(boundingBox(collision.shape, frame * collision.origin));
  }
  if (box.isEmpty())
    box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.05), Eigen::Vector3d::Constant(0.05));
  const Eigen::Vector3d size = box.sizes().cwiseMax(0.01);
  MassProperties solid;
  solid.mass = mass;
  solid.com = com.value_or(box.center());
  solid.inertia =
      (mass / 12 *
       Eigen::Vector3d(size.y() * size.y() + size.z() * size.z(), size.x() * size.x() + size.z() * size.z(),
                       size.x() * size.x() + size.y() * size.y()))
          .asDiagonal();
  return solid;
}

LinkSpec& linkNamed(ModelSpec& model, const std::string& name) {
  return *std::find_if(model.links.begin(), model.links.end(),
                       [&](const LinkSpec& l) { return l.name == name; });
}

}  // namespace

void repairBodyInertias(ModelSpec& model, Diagnostics& diagnostics,
                        const std::set<std::string>& refused_links) {
  std::set<std::string> faulty = refused_links;  // links whose body is refused: nothing to mend
  for (const LinkSpec& link : model.links) {
    if (!link.inertial || !(link.inertial->mass < 0)) continue;
    std::ostringstream message;
    message << "link [" << link.name << "] <inertial>: mass " << link.inertial->mass << " kg is not positive";
    diagnostics.error(message.str());
    faulty.insert(link.name);
  }
  if (model.is_static) return;  // nothing of it moves
  const auto bodies = rigidBodies(model);
  double robot_mass = 0;
  for (const auto& body : bodies) robot_mass += std::max(0.0, combineInertia(model, body).mass);
  for (size_t k = model.root == "world" ? 1 : 0; k < bodies.size(); ++k) {
    const bool refused = std::any_of(bodies[k].begin(), bodies[k].end(),
                                     [&](const auto& placed) { return faulty.count(placed.first) > 0; });
    if (refused) continue;
    const MassProperties lumped = combineInertia(model, bodies[k]);
    const bool has_mass = lumped.mass > 0;
    const std::optional<std::string> problem =
        has_mass ? inertiaProblem(lumped.mass, lumped.inertia) : std::optional<std::string>("it has no mass");
    if (!problem) continue;
    const MassProperties solid =
        boxBody(model, bodies[k], has_mass ? lumped.mass : std::max(0.01, robot_mass / 100),
                has_mass ? std::optional(lumped.com) : std::nullopt);
    std::ostringstream message;
    message << "link [" << bodies[k].front().first << "]"
            << (bodies[k].size() > 1 ? " with the links fixed to it, lumped as Gazebo does," : "") << ": "
            << *problem << "; it is simulated as a solid box of " << solid.mass
            << " kg filling its collisions' bounding box (principal moments "
            << solid.inertia.diagonal().transpose() << " kg m^2)";
    diagnostics.warning(message.str());
    for (const auto& placed : bodies[k]) linkNamed(model, placed.first).inertial.reset();
    // The body's first link, whose frame is the body's, carries it all.
    linkNamed(model, bodies[k].front().first).inertial = InertialSpec{solid.mass, solid.com, solid.inertia};
  }
}

}  // namespace bullet_sim
