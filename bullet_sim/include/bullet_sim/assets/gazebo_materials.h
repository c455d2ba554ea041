// Colours of Gazebo classic's named materials (media/materials/scripts/gazebo.material) and of the OGRE
// material scripts a world or package brings, for visuals that name a material instead of giving a colour.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

/// RGBA in [0, 1] of a Gazebo material such as "Gazebo/Grey" (every surface material of Gazebo 11's
/// gazebo.material), or nullopt for a name not in the table. Textured materials (Gazebo/Wood, Gazebo/Grass,
/// ...) get their texture's average colour; see-through ones (Gazebo/RedTransparent) an alpha below 1.
std::optional<Eigen::Vector4d> gazeboMaterialColour(const std::string& name);

/// Every name gazeboMaterialColour knows, for "did you mean" hints.
std::vector<std::string> gazeboMaterialNames();

/// RGBA of material `name` as the OGRE material scripts `files` (the .material files that a visual's
/// <script><uri>s name) define it: the first diffuse colour in its block, else the first ambient one,
/// through `material NAME : PARENT` inheritance; the first file that defines a name wins. A texture the
/// material names (its first texture_unit's) multiplies that colour (white when it gives none) by its mean
/// colour, as a surface shows it from afar; it is looked for beside the script, in the textures folder beside
/// the script's folder, then in `texture_folders`. nullopt when no file defines the name, or it has neither a
/// colour nor a texture that could be read. `warning` (when given) says why a named texture was not used.
std::optional<Eigen::Vector4d> scriptMaterialColour(const std::string& name,
                                                    const std::vector<std::string>& files,
                                                    const std::vector<std::string>& texture_folders = {},
                                                    std::string* warning = nullptr);

/// The .material files in `folder`, sorted by name; none when it is not a folder.
std::vector<std::string> materialScriptsIn(const std::string& folder);

/// The material scripts Gazebo loads for every visual, a URDF's included: those in media/materials/scripts
/// of each folder of `resource_path` (GAZEBO_RESOURCE_PATH, then the packages' gazebo_media_path exports).
std::vector<std::string> resourceMaterialScripts(const std::vector<std::string>& resource_path);

/// The folders of `resource_path` where Gazebo finds the textures that material scripts name:
/// media/materials/textures of each.
std::vector<std::string> resourceTextureFolders(const std::vector<std::string>& resource_path);

}  // namespace bullet_sim
