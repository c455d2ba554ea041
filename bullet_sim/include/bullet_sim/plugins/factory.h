// Turns a model's Gazebo <plugin> and <sensor> declarations into plugins.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct PluginContext {
  std::string robot_name;  ///< seeds each plugin's noise together with `seed`
  uint64_t seed = 0;
  Eigen::Vector3d gravity{0, 0, -9.81};
  std::function<BodyId(int part)> ray_body;  ///< the ray-caster body of a robot part
};

/// One plugin per declaration we simulate. Unknown plugin filenames and sensors we do not simulate get one
/// warning each; configuration problems are errors. Everything goes to `diagnostics`.
std::vector<std::unique_ptr<Plugin>> createPlugins(const ModelSpec& model, const RobotBody& body,
                                                   const PluginContext& context, Diagnostics& diagnostics);

}  // namespace bullet_sim
