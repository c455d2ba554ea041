#include "physics/robot_parts.h"

#include <algorithm>

namespace bullet_sim {

PartLayout partitionAtMovingJoints(const ModelSpec& model) {
  PartLayout layout;
  layout.parts.push_back({model.root, {model.root}, {}});
  layout.link_in_part.push_back({{model.root, Eigen::Isometry3d::Identity()}});
  layout.parent.push_back(-1);
  layout.joint.push_back(nullptr);
  layout.part_of_link[model.root] = 0;
  for (const auto& joint : model.joints) {  // parents come before children
    int part = layout.part_of_link.at(joint.parent);
    if (joint.moves()) {
      layout.parent.push_back(part);
      part = static_cast<int>(layout.parts.size());
      layout.parts.push_back({joint.child, {joint.child}, {}});
      layout.link_in_part.push_back({{joint.child, Eigen::Isometry3d::Identity()}});
      layout.joint.push_back(&joint);
    } else {
      layout.parts[part].links.push_back(joint.child);
      layout.link_in_part[part][joint.child] = layout.link_in_part[part].at(joint.parent) * joint.origin;
    }
    layout.part_of_link[joint.child] = part;
  }
  for (size_t k = 0; k < layout.parts.size(); ++k) {
    for (const auto& name : layout.parts[k].links) {
      const Eigen::Isometry3d& in_part = layout.link_in_part[k].at(name);
      const auto& collisions = model.link(name)->collisions;
      for (size_t i = 0; i < collisions.size(); ++i) {
        layout.parts[k].collisions.push_back(
            {in_part * collisions[i].origin, collisions[i].shape, collisions[i].name});
        layout.parts[k].sources.push_back({name, static_cast<int>(i)});
      }
    }
  }
  return layout;
}

bool checkMovingPart(const RobotPart& part, double mass, Diagnostics& diagnostics) {
  if (mass <= 0) {
    diagnostics.error("links [" + part.root_link +
                      "] and those fixed to it have no mass: give one an <inertial>");
    return false;
  }
  const auto plane = [](const Collision& collision) { return collision.shape.type == Shape::Type::kPlane; };
  if (std::none_of(part.collisions.begin(), part.collisions.end(), plane)) return true;
  diagnostics.error("link [" + part.root_link + "] collides with a plane, which only static worlds may have");
  return false;
}

}  // namespace bullet_sim
