#include "bullet_sim/assets/gazebo_materials.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "bullet_sim/assets/texture.h"

namespace bullet_sim {

namespace {

struct NamedColour {
  const char* name;
  std::array<double, 4> rgba;
};

// The surface materials of Gazebo classic 11's media/materials/scripts/gazebo.material: their diffuse colour,
// else their ambient one; the alpha of the see-through ones (their alpha_op_ex). Gazebo/SkyBlue keeps its
// ambient sky blue (its diffuse is plain blue). Gray and DarkGray are the file's aliases of Grey and
// DarkGrey.
// A textured material gets its texture's average colour times its diffuse: measured for Wood, WoodPallet and
// CloudySky from Gazebo's images, estimated from what the others show (bullet_sim ships no Gazebo media).
// The shader-only materials (DepthMap, LaserScan1st, PointCloud, ...) colour no surface and are not listed.
constexpr NamedColour kColours[] = {
    {"Gazebo/Grey", {0.7, 0.7, 0.7, 1}},
    {"Gazebo/Gray", {0.7, 0.7, 0.7, 1}},
    {"Gazebo/DarkGrey", {0.175, 0.175, 0.175, 1}},
    {"Gazebo/DarkGray", {0.175, 0.175, 0.175, 1}},
    {"Gazebo/White", {1, 1, 1, 1}},
    {"Gazebo/FlatBlack", {0.1, 0.1, 0.1, 1}},
    {"Gazebo/Black", {0, 0, 0, 1}},
    {"Gazebo/Red", {1, 0, 0, 1}},
    {"Gazebo/RedBright", {0.87, 0.26, 0.07, 1}},
    {"Gazebo/Green", {0, 1, 0, 1}},
    {"Gazebo/Blue", {0, 0, 1, 1}},
    {"Gazebo/SkyBlue", {0.13, 0.44, 0.70, 1}},
    {"Gazebo/Yellow", {1, 1, 0, 1}},
    {"Gazebo/ZincYellow", {0.9725, 0.9529, 0.2078, 1}},
    {"Gazebo/DarkYellow", {0.7, 0.7, 0, 1}},
    {"Gazebo/Purple", {1, 0, 1, 1}},
    {"Gazebo/Turquoise", {0, 1, 1, 1}},
    {"Gazebo/Orange", {1, 0.5088, 0.0468, 1}},
    {"Gazebo/Indigo", {0.33, 0, 0.5, 1}},
    {"Gazebo/WhiteGlow", {1, 1, 1, 1}},
    {"Gazebo/RedGlow", {1, 0, 0, 1}},
    {"Gazebo/GreenGlow", {0, 1, 0, 1}},
    {"Gazebo/BlueGlow", {0, 0, 1, 1}},
    {"Gazebo/YellowGlow", {1, 1, 0, 1}},
    {"Gazebo/PurpleGlow", {1, 0, 1, 1}},
    {"Gazebo/TurquoiseGlow", {0, 1, 1, 1}},
    {"Gazebo/TurquoiseGlowOutline", {0, 1, 1, 1}},
    {"Gazebo/RedTransparentOverlay", {1, 0, 0, 0.5}},
    {"Gazebo/BlueTransparentOverlay", {0, 0, 1, 0.5}},
    {"Gazebo/GreenTransparentOverlay", {0, 1, 0, 0.5}},
    {"Gazebo/OrangeTransparentOverlay", {1, 0.5088, 0.0468, 0.8}},
    {"Gazebo/DarkOrangeTransparentOverlay", {0.6, 0.305, 0.028, 0.8}},
    {"Gazebo/RedTransparent", {1, 0, 0, 0.5}},
    {"Gazebo/GreenTransparent", {0, 1, 0, 0.5}},
    {"Gazebo/BlueTransparent", {0, 0, 1, 0.5}},
    {"Gazebo/DarkMagentaTransparent", {0.6, 0, 0.6, 0.5}},
    {"Gazebo/GreyTransparent", {0.5, 0.5, 0.5, 0.5}},
    {"Gazebo/BlackTransparent", {0, 0, 0, 0.5}},
    {"Gazebo/YellowTransparent", {1, 1, 0, 0.5}},
    {"Gazebo/LightOn", {0, 1, 0, 1}},
    {"Gazebo/LightOff", {1, 0, 0, 1}},
    {"Gazebo/LightBlueLaser", {0.5, 0.5, 1, 0.4}},
    {"Gazebo/BlueLaser", {0, 0, 1, 0.4}},
    {"Gazebo/OrangeTransparent", {1, 0.44, 0, 0.4}},
    {"Gazebo/JointAnchor", {1, 1, 1, 1}},
    {"Gazebo/CoM", {0.5, 0.5, 0.5, 1}},
    {"Gazebo/WoodFloor", {0.6, 0.42, 0.26, 1}},
    {"Gazebo/CeilingTiled", {0.85, 0.85, 0.82, 1}},
    {"Gazebo/PaintedWall", {0.9, 0.89, 0.85, 1}},
    {"Gazebo/PioneerBody", {0.7, 0.05, 0.05, 1}},
    {"Gazebo/Pioneer2Body", {0.681193, 0.000923, 0.000923, 1}},
    {"Gazebo/Gold", {0.8, 0.64869, 0.120759, 1}},
    {"Gazebo/GreyGradientSky", {0.7, 0.7, 0.7, 1}},
    {"Gazebo/CloudySky", {0.582, 0.739, 0.995, 1}},
    {"Gazebo/WoodPallet", {0.542, 0.383, 0.184, 1}},
    {"Gazebo/Wood", {0.740, 0.653, 0.643, 1}},
    {"Gazebo/Bricks", {0.6, 0.3, 0.22, 1}},
    {"Gazebo/WindowFrame", {0.85, 0.85, 0.85, 1}},
    {"Gazebo/Road", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Residential", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Tertiary", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Pedestrian", {0.48, 0.48, 0.46, 1}},
    {"Gazebo/Footway", {0.48, 0.48, 0.46, 1}},
    {"Gazebo/Motorway", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Lanes_6", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Trunk", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Lanes_4", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Primary", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Lanes_2", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Secondary", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Lane_1", {0.28, 0.28, 0.28, 1}},
    {"Gazebo/Steps", {0.45, 0.45, 0.45, 1}},
    {"drc/san_fauxcity_sign", {0.7, 0.7, 0.7, 1}},
    {"Gazebo/BuildingFrame", {0.85, 0.85, 0.85, 1}},
    {"Gazebo/Runway", {0.35, 0.35, 0.35, 1}},
    {"Gazebo/Grass", {0.3, 0.45, 0.15, 1}},
    {"Gazebo/Editor", {1, 1, 1, 1}},
    {"Gazebo/EditorPlane", {0.7, 0.7, 0.7, 1}},
};

/// A material block of an OGRE script: its colours, its first texture and the material it inherits from.
struct ScriptMaterial {
  std::optional<Eigen::Vector4d> diffuse;
  std::optional<Eigen::Vector4d> ambient;
  std::string texture;  ///< the image file its first texture_unit names, as written
  std::string script;   ///< the .material file it is in
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

/// Adds the material blocks of `words`, read from `script`, that `materials` does not hold yet.
void readMaterials(const std::vector<std::string>& words, const std::string& script,
                   std::map<std::string, ScriptMaterial>& materials) {
  for (size_t i = 0; i + 1 < words.size(); ++i) {
    if (words[i] != "material") continue;
    const std::string name = words[i + 1];
    ScriptMaterial material;
    material.script = script;
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
      if (words[at] == "texture" && material.texture.empty() && at + 1 < words.size() && words[at + 1] != "}")
        material.texture = words[at + 1];
    }
    materials.emplace(name, material);
    i = at;
  }
}

/// Material `name` with what it inherits filled in (each of its colours and its texture from the nearest
/// block that has one); nullopt when no block defines it.
std::optional<ScriptMaterial> resolved(const std::string& name,
                                       const std::map<std::string, ScriptMaterial>& materials) {
  std::optional<ScriptMaterial> result;
  std::string current = name;
  for (size_t depth = 0; depth <= materials.size(); ++depth) {  // a cycle of parents ends here
    const auto found = materials.find(current);
    if (found == materials.end()) break;
    const ScriptMaterial& block = found->second;
    if (!result) result = ScriptMaterial{};
    if (!result->diffuse) result->diffuse = block.diffuse;
    if (!result->ambient) result->ambient = block.ambient;
    if (result->texture.empty() && !block.texture.empty()) {
      result->texture = block.texture;
      result->script = block.script;
    }
    current = block.parent;
  }
  return result;
}

/// The mean RGBA of the image `texture` that `script` names: looked for beside the script, in the textures
/// folder beside its folder (a model's materials/textures), then in `folders`. nullopt with `warning` saying
/// why when it is not found or cannot be decoded.
std::optional<Eigen::Vector4d> averageTexture(const std::string& texture, const std::string& script,
                                              const std::vector<std::string>& folders, std::string* warning) {
  namespace fs = std::filesystem;
  const fs::path beside = fs::path(script).parent_path();
  std::vector<fs::path> candidates = {beside / texture, beside.parent_path() / "textures" / texture};
  for (const std::string& folder : folders) candidates.push_back(fs::path(folder) / texture);
  std::error_code ec;
  const auto found = std::find_if(candidates.begin(), candidates.end(), [&](const fs::path& candidate) {
    return fs::is_regular_file(candidate, ec);
  });
  if (found == candidates.end()) {
    *warning = "its texture [" + texture + "] was not found beside its script [" + script +
               "], in a textures folder beside that, in its <uri>s' folders or in the resource path's "
               "media/materials/textures";
    return std::nullopt;
  }
  std::string error;
  const std::optional<Texture> image = loadTexture(found->string(), &error);
  if (!image || image->rgba.empty()) {
    *warning = "its texture: " + error;
    return std::nullopt;
  }
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  for (size_t at = 0; at < image->rgba.size(); at += 4) {
    sum += Eigen::Vector4d(image->rgba[at], image->rgba[at + 1], image->rgba[at + 2], image->rgba[at + 3]);
  }
  return sum / (255.0 * static_cast<double>(image->rgba.size() / 4));
}

}  // namespace

std::optional<Eigen::Vector4d> scriptMaterialColour(const std::string& name,
                                                    const std::vector<std::string>& files,
                                                    const std::vector<std::string>& texture_folders,
                                                    std::string* warning) {
  std::map<std::string, ScriptMaterial> materials;
  for (const auto& file : files) {
    std::ifstream in(file);
    readMaterials(scriptWords(in), file, materials);
  }
  const std::optional<ScriptMaterial> material = resolved(name, materials);
  if (!material) return std::nullopt;
  const std::optional<Eigen::Vector4d> colour = material->diffuse ? material->diffuse : material->ambient;
  if (material->texture.empty()) return colour;
  // The texture multiplies the lit colour, white unless the script gives one.
  std::string why;
  const std::optional<Eigen::Vector4d> average =
      averageTexture(material->texture, material->script, texture_folders, &why);
  if (!average) {
    if (warning) *warning = why;
    return colour;
  }
  return colour.value_or(Eigen::Vector4d::Ones()).cwiseProduct(*average);
}

std::vector<std::string> materialScriptsIn(const std::string& folder) {
  std::vector<std::string> scripts;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().extension() == ".material") scripts.push_back(it->path().string());
  }
  std::sort(scripts.begin(), scripts.end());
  return scripts;
}

std::vector<std::string> resourceMaterialScripts(const std::vector<std::string>& resource_path) {
  std::vector<std::string> scripts;
  for (const std::string& folder : resource_path) {
    const std::vector<std::string> found = materialScriptsIn(folder + "/media/materials/scripts");
    scripts.insert(scripts.end(), found.begin(), found.end());
  }
  return scripts;
}

std::vector<std::string> resourceTextureFolders(const std::vector<std::string>& resource_path) {
  std::vector<std::string> folders;
  for (const std::string& folder : resource_path) folders.push_back(folder + "/media/materials/textures");
  return folders;
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
