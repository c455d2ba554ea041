#include "bullet_sim/scene/scene.h"

#include <algorithm>

namespace bullet_sim {

Eigen::Vector3d Lighting::shade(const Eigen::Vector4d& rgba, const Eigen::Vector3d& normal) const {
  const double facing = std::max(0.0, normal.normalized().dot(-direction.normalized()));
  return (rgba.head<3>() * (ambient + diffuse * facing)).cwiseMin(1.0);
}

}  // namespace bullet_sim
