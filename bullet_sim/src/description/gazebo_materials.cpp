#include "bullet_sim/description/gazebo_materials.h"

#include <array>
#include <utility>

namespace bullet_sim {

namespace {

struct NamedColour {
  const char* name;
  std::array<double, 4> rgba;
};

// Diffuse colours from gazebo.material; where a material has no diffuse (or only a texture), its ambient or
// the texture's average colour. "Gazebo/Gray" is not in gazebo.material, but URDFs use it as "Gazebo/Grey".
constexpr NamedColour kColours[] = {
    {"Gazebo/Grey", {0.7, 0.7, 0.7, 1}},
    {"Gazebo/Gray", {0.7, 0.7, 0.7, 1}},
    {"Gazebo/DarkGrey", {0.175, 0.175, 0.175, 1}},
    {"Gazebo/White", {1, 1, 1, 1}},
    {"Gazebo/Black", {0, 0, 0, 1}},
    {"Gazebo/FlatBlack", {0.1, 0.1, 0.1, 1}},
    {"Gazebo/Red", {1, 0, 0, 1}},
    {"Gazebo/RedBright", {0.87, 0.26, 0.07, 1}},
    {"Gazebo/Green", {0, 1, 0, 1}},
    {"Gazebo/Blue", {0, 0, 1, 1}},
    {"Gazebo/SkyBlue", {0.13, 0.44, 0.70, 1}},
    {"Gazebo/Yellow", {1, 1, 0, 1}},
    {"Gazebo/ZincYellow", {0.9725, 0.9529, 0.2078, 1}},
    {"Gazebo/Orange", {1, 0.5088, 0.0468, 1}},
    {"Gazebo/Purple", {1, 0, 1, 1}},
    {"Gazebo/Turquoise", {0, 1, 1, 1}},
    {"Gazebo/Gold", {0.8, 0.64869, 0.120759, 1}},
    {"Gazebo/Wood", {0.55, 0.36, 0.2, 1}},
    {"Gazebo/WoodFloor", {0.6, 0.42, 0.26, 1}},
    {"Gazebo/WoodPallet", {0.62, 0.5, 0.36, 1}},
    {"Gazebo/Bricks", {0.6, 0.3, 0.22, 1}},
    {"Gazebo/PaintedWall", {0.9, 0.89, 0.85, 1}},
};

}  // namespace

std::optional<Eigen::Vector4d> gazeboMaterialColour(const std::string& name) {
  for (const auto& colour : kColours) {
    if (name == colour.name) return Eigen::Map<const Eigen::Vector4d>(colour.rgba.data());
  }
  return std::nullopt;
}

std::vector<std::string> gazeboMaterialNames() {
  std::vector<std::string> names;
  for (const auto& colour : kColours) names.emplace_back(colour.name);
  return names;
}

}  // namespace bullet_sim
