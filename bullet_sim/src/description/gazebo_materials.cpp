#include "bullet_sim/description/gazebo_materials.h"

#include <array>
#include <fstream>
#include <map>
#include <sstream>
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

/// A material block of an OGRE script: its colours and the material it inherits from.
struct ScriptMaterial {
  std::optional<Eigen::Vector4d> diffuse;
  std::optional<Eigen::Vector4d> ambient;
  std::string parent;
};

/// The words of an OGRE script: "//" comments dropped, each brace a word of its own.
std::vector<std::string> scriptWords(std::istream& in) {
  std::vector<std::string> words;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find("//"));
    std::string spaced;
    for (char c : line) spaced += (c == '{' || c == '}') ? std::string(" ") + c + " " : std::string(1, c);
    std::istringstream split(spaced);
    for (std::string word; split >> word;) words.push_back(word);
  }
  return words;
}

/// "r g b [a]" starting at words[at]; nullopt for anything else (such as "vertexcolour").
std::optional<Eigen::Vector4d> colourAt(const std::vector<std::string>& words, size_t at) {
  Eigen::Vector4d rgba(0, 0, 0, 1);
  for (int i = 0; i < 4; ++i) {
    try {
      size_t used = 0;
      if (at + i >= words.size()) throw std::invalid_argument("end");
      rgba[i] = std::stod(words[at + i], &used);
      if (used != words[at + i].size()) throw std::invalid_argument(words[at + i]);
    } catch (const std::exception&) {
      if (i < 3) return std::nullopt;
      break;
    }
  }
  return rgba;
}

/// Adds the material blocks of `words` that `materials` does not hold yet.
void readMaterials(const std::vector<std::string>& words, std::map<std::string, ScriptMaterial>& materials) {
  for (size_t i = 0; i + 1 < words.size(); ++i) {
    if (words[i] != "material") continue;
    const std::string name = words[i + 1];
    ScriptMaterial material;
    size_t at = i + 2;
    if (at + 1 < words.size() && words[at] == ":") {
      material.parent = words[at + 1];
      at += 2;
    }
    if (at >= words.size() || words[at] != "{") continue;
    for (int depth = 0; at < words.size(); ++at) {
      if (words[at] == "{") ++depth;
      if (words[at] == "}" && --depth == 0) break;
      if (words[at] == "diffuse" && !material.diffuse) material.diffuse = colourAt(words, at + 1);
      if (words[at] == "ambient" && !material.ambient) material.ambient = colourAt(words, at + 1);
    }
    materials.emplace(name, material);
    i = at;
  }
}

}  // namespace

std::optional<Eigen::Vector4d> scriptMaterialColour(const std::string& name,
                                                    const std::vector<std::string>& files) {
  std::map<std::string, ScriptMaterial> materials;
  for (const auto& file : files) {
    std::ifstream in(file);
    readMaterials(scriptWords(in), materials);
  }
  std::string current = name;
  for (size_t depth = 0; depth <= materials.size(); ++depth) {  // a cycle of parents ends here
    const auto found = materials.find(current);
    if (found == materials.end()) return std::nullopt;
    if (found->second.diffuse) return found->second.diffuse;
    if (found->second.ambient) return found->second.ambient;
    current = found->second.parent;
  }
  return std::nullopt;
}

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
