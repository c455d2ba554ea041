// The names Gazebo gives a URDF's links and collisions once it has turned the URDF into SDF (sdformat 9, as
// Gazebo 11 on Noetic): fixed-joint lumping moves a link's collisions into the nearest ancestor on a moving
// joint (or a joint whose lumping is disabled), and renames them. Contact sensors and their reports use
// these names.
//
// The rule, per SDF link L and its collisions in order (L's own, then those of the links lumped into it, in
// the tree's order: children by joint name): the k-th is named <base>_collision, or <base>_collision_<k> for
// k > 0, where <base> is the URDF collision's name, or else the name of the URDF link that declared it; a
// name that does not start with L's gets the prefix L_fixed_joint_lump__.
#pragma once

#include <string>
#include <vector>

namespace bullet_sim {

struct ModelSpec;

/// The link `link`'s collisions and sensors land in after fixed-joint lumping: itself when its joint moves,
/// when lumping is disabled on it, or when it is the root.
std::string gazeboLink(const ModelSpec& model, const std::string& link);

/// A URDF collision as Gazebo names it.
struct GazeboCollision {
  std::string link;         ///< the URDF link that declares it
  int index = 0;            ///< among that link's collisions
  std::string gazebo_link;  ///< the link it lands in
  std::string name;         ///< its name there
};

/// Every collision of the model, as Gazebo names it.
std::vector<GazeboCollision> gazeboCollisions(const ModelSpec& model);

/// The names `link`'s collisions would have if Gazebo did not lump it: what users write for a link that is
/// in fact lumped (and what Gazebo then never finds).
std::vector<std::string> unlumpedCollisionNames(const ModelSpec& model, const std::string& link);

}  // namespace bullet_sim
