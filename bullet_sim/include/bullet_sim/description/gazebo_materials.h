// Colours of Gazebo classic's named materials (media/materials/scripts/gazebo.material), for visuals that
// name a material script instead of giving a colour.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

/// RGBA in [0, 1] of a Gazebo material such as "Gazebo/Grey", or nullopt for a name not in the table.
/// Textured materials (Gazebo/Wood, Gazebo/WoodFloor, ...) get their texture's average colour.
std::optional<Eigen::Vector4d> gazeboMaterialColour(const std::string& name);

/// Every name gazeboMaterialColour knows, for "did you mean" hints.
std::vector<std::string> gazeboMaterialNames();

/// RGBA of material `name` as the OGRE material scripts `files` (the .material files that a visual's
/// <script><uri>s name) define it: the first diffuse colour in its block, else the first ambient one,
/// through `material NAME : PARENT` inheritance. nullopt when no file defines it with a colour; the first
/// file that defines a name wins. Textures are not read.
std::optional<Eigen::Vector4d> scriptMaterialColour(const std::string& name,
                                                    const std::vector<std::string>& files);

}  // namespace bullet_sim
