#include "bullet_sim/assets/gazebo_paths.h"

#include <sdf/sdf_config.h>  // SDF_VERSION: the newest SDF version libsdformat reads
#include <tinyxml2.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/names.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

std::vector<std::string> splitPath(const char* value) {
  std::vector<std::string> entries;
  std::stringstream text(value ? value : "");
  for (std::string entry; std::getline(text, entry, ':');) {
    if (!entry.empty()) entries.push_back(entry);
  }
  return entries;
}

/// Appends the entries of `from` that `to` does not hold yet.
void appendNew(std::vector<std::string>& to, const std::vector<std::string>& from) {
  for (const auto& entry : from) {
    if (std::find(to.begin(), to.end(), entry) == to.end()) to.push_back(entry);
  }
}

/// "1.6" -> {1, 6}; what is not a version sorts first.
std::pair<int, int> versionOf(const char* text) {
  int major = 0, minor = 0;
  if (!text || std::sscanf(text, "%d.%d", &major, &minor) < 1) return {-1, -1};
  return {major, minor};
}

}  // namespace

GazeboEnvironment GazeboEnvironment::fromEnvironment() {
  GazeboEnvironment environment;
  environment.model_path = splitPath(std::getenv("GAZEBO_MODEL_PATH"));
  environment.resource_path = splitPath(std::getenv("GAZEBO_RESOURCE_PATH"));
  const char* home = std::getenv("HOME");
  environment.home = home ? home : "";
  return environment;
}

GazeboExports readGazeboExports(const std::string& package_dir) {
  GazeboExports exports;
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile((fs::path(package_dir) / "package.xml").c_str()) != tinyxml2::XML_SUCCESS) return exports;
  const tinyxml2::XMLElement* root = doc.RootElement();
  const tinyxml2::XMLElement* export_element = root ? root->FirstChildElement("export") : nullptr;
  if (!export_element) return exports;
  const auto expand = [&](std::string value) {
    const std::string prefix = "${prefix}";
    for (size_t at = value.find(prefix); at != std::string::npos; at = value.find(prefix, at)) {
      value.replace(at, prefix.size(), package_dir);
      at += package_dir.size();
    }
    return fs::path(value).lexically_normal().string();
  };
  for (const tinyxml2::XMLElement* entry = export_element->FirstChildElement("gazebo_ros"); entry;
       entry = entry->NextSiblingElement("gazebo_ros")) {
    if (const char* value = entry->Attribute("gazebo_model_path"))
      exports.model_path.push_back(expand(value));
    if (const char* value = entry->Attribute("gazebo_media_path"))
      exports.media_path.push_back(expand(value));
  }
  return exports;
}

GazeboPaths::GazeboPaths(const GazeboEnvironment& environment, const std::vector<GazeboExports>& exports,
                         const std::string& shipped_models, const std::string& shipped_media) {
  appendNew(model_path_, environment.model_path);
  for (const auto& package : exports) appendNew(model_path_, package.model_path);
  if (!shipped_models.empty()) appendNew(model_path_, {shipped_models});
  if (!environment.home.empty())
    appendNew(model_path_, {(fs::path(environment.home) / ".gazebo/models").string()});

  appendNew(resource_path_, environment.resource_path);
  if (!shipped_media.empty()) appendNew(resource_path_, {shipped_media});
  for (const auto& package : exports) appendNew(resource_path_, package.media_path);
}

std::optional<std::string> GazeboPaths::findModelFile(const std::string& relative, std::string* error) const {
  std::error_code ec;
  for (const auto& folder : model_path_) {
    const fs::path candidate = fs::path(folder) / relative;
    if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
  }
  if (error) {
    const std::string name = relative.substr(0, relative.find('/'));
    const bool known = name != relative &&
                       std::any_of(model_path_.begin(), model_path_.end(),
                                   [&](const auto& f) { return fs::is_directory(fs::path(f) / name, ec); });
    *error =
        (known ? "model [" + name + "] has no file [" + relative.substr(name.size() + 1) + "]"
               : "unknown model [" + name + "]" + didYouMean(name, modelNames())) +
        "; the model path is " + joinedNames(model_path_, "(none)") +
        ". To add a model, put its folder (with its " +
        "model.config) into one of them, or add the folder that holds it to GAZEBO_MODEL_PATH, or export " +
        "that folder from your package.xml: <export><gazebo_ros gazebo_model_path=\"${prefix}/models\"/>" +
        "</export>. Models are never downloaded";
  }
  return std::nullopt;
}

std::vector<std::string> GazeboPaths::modelNames() const {
  std::set<std::string> names;
  std::error_code ec;
  for (const auto& folder : model_path_) {
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->is_directory(ec)) names.insert(it->path().filename().string());
    }
  }
  return {names.begin(), names.end()};
}

std::optional<std::string> modelSdfFile(const std::string& model_dir, std::string* error) {
  const fs::path config = fs::path(model_dir) / "model.config";
  const std::string fix =
      "; a model folder holds a model.config such as <model><name>NAME</name>"
      "<sdf version=\"1.6\">model.sdf</sdf></model>";
  tinyxml2::XMLDocument doc;
  std::error_code ec;
  if (!fs::is_regular_file(config, ec)) {
    *error = "model folder [" + model_dir + "] has no model.config" + fix;
    return std::nullopt;
  }
  if (doc.LoadFile(config.c_str()) != tinyxml2::XML_SUCCESS) {
    *error = "[" + config.string() + ":" + std::to_string(doc.ErrorLineNum()) +
             "] malformed XML: " + doc.ErrorStr() + "; fix the XML there";
    return std::nullopt;
  }
  const tinyxml2::XMLElement* model = doc.RootElement();
  const tinyxml2::XMLElement* best = model ? model->FirstChildElement("sdf") : nullptr;
  // Gazebo's rule: the highest version that the parser reads; the first <sdf> when none has a version.
  std::pair<int, int> best_version{-1, -1};
  const std::pair<int, int> newest = versionOf(SDF_VERSION);
  for (const tinyxml2::XMLElement* sdf = best; sdf; sdf = sdf->NextSiblingElement("sdf")) {
    const std::pair<int, int> version = versionOf(sdf->Attribute("version"));
    if (version > best_version && version <= newest) {
      best = sdf;
      best_version = version;
    }
  }
  if (!model || std::string(model->Name()) != "model" || !best || !best->GetText()) {
    *error = "[" + config.string() + "] names no SDF file" + fix;
    return std::nullopt;
  }
  const fs::path file = fs::path(model_dir) / best->GetText();
  if (!fs::is_regular_file(file, ec)) {
    *error = "[" + config.string() + "] names the SDF file [" + std::string(best->GetText()) +
             "], which does not exist; fix the name in its <sdf> element";
    return std::nullopt;
  }
  return file.lexically_normal().string();
}

}  // namespace bullet_sim
