#include "bullet_sim/model/gazebo_names.h"

#include "bullet_sim/model/model.h"

namespace bullet_sim {

namespace {

constexpr char kLumpPrefix[] = "_fixed_joint_lump__";

/// The name of the `index`-th collision of SDF link `sdf_link`, from its URDF name or link (`base`).
std::string collisionName(const std::string& sdf_link, const std::string& base, int index) {
  std::string name = base + "_collision";
  if (index > 0) name += "_" + std::to_string(index);
  if (name.compare(0, sdf_link.size(), sdf_link) != 0) name = sdf_link + kLumpPrefix + name;
  return name;
}

}  // namespace

std::string gazeboLink(const ModelSpec& model, const std::string& link) {
  if (model.names_from_sdf) return link;  // Gazebo lumps no SDF link
  std::string current = link;
  for (const JointSpec* joint = model.parentJoint(current); joint && !joint->moves();
       joint = model.parentJoint(current)) {
    if (joint->lumping_disabled) break;
    current = joint->parent;
  }
  return current;
}

std::vector<GazeboCollision> gazeboCollisions(const ModelSpec& model) {
  std::vector<GazeboCollision> named;
  std::vector<std::string> sdf_links;  // per model.links entry
  for (const auto& link : model.links) sdf_links.push_back(gazeboLink(model, link.name));
  // Each SDF link takes its own collisions, then those lumped into it, in the tree's (model.links') order.
  for (const auto& sdf_link : model.links) {
    int count = 0;
    for (size_t l = 0; l < model.links.size(); ++l) {
      if (sdf_links[l] != sdf_link.name) continue;
      const LinkSpec& link = model.links[l];
      for (size_t i = 0; i < link.collisions.size(); ++i) {
        const std::string& base = link.collisions[i].name.empty() ? link.name : link.collisions[i].name;
        named.push_back({link.name, static_cast<int>(i), sdf_link.name,
                         model.names_from_sdf ? base : collisionName(sdf_link.name, base, count)});
        ++count;
      }
    }
  }
  return named;
}

std::vector<std::string> unlumpedCollisionNames(const ModelSpec& model, const std::string& link) {
  std::vector<std::string> names;
  if (const LinkSpec* spec = model.link(link)) {
    for (size_t i = 0; i < spec->collisions.size(); ++i) {
      const std::string& base = spec->collisions[i].name.empty() ? link : spec->collisions[i].name;
      names.push_back(collisionName(link, base, static_cast<int>(i)));
    }
  }
  return names;
}

}  // namespace bullet_sim
