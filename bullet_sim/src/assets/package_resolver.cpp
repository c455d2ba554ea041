#include "bullet_sim/assets/package_resolver.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxCrawlDepth = 4;

std::optional<std::string> manifestName(const fs::path& dir) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile((dir / "package.xml").c_str()) != tinyxml2::XML_SUCCESS) return std::nullopt;
  const tinyxml2::XMLElement* name =
      doc.RootElement() ? doc.RootElement()->FirstChildElement("name") : nullptr;
  if (!name || !name->GetText()) return std::nullopt;
  return std::string(name->GetText());
}

// Like rospack: a directory holding package.xml is a package and is not descended into; CATKIN_IGNORE hides
// one. `visit` returns true to stop the crawl.
bool crawl(const fs::path& dir, int depth, const std::function<bool(const fs::path&)>& visit) {
  std::error_code ec;
  if (fs::exists(dir / "CATKIN_IGNORE", ec)) return false;
  if (fs::exists(dir / "package.xml", ec)) return visit(dir);
  if (depth == 0) return false;
  std::vector<fs::path> subdirectories;  // sorted, so that the first package of a name is always the same
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_directory(ec) && it->path().filename().string().front() != '.') subdirectories.push_back(*it);
  }
  std::sort(subdirectories.begin(), subdirectories.end());
  for (const auto& subdirectory : subdirectories) {
    if (crawl(subdirectory, depth - 1, visit)) return true;
  }
  return false;
}

/// The models bullet_sim ships: in its package when the search path has it, else in its source tree.
std::string shippedModels(const std::optional<std::string>& bullet_sim_directory) {
  std::error_code ec;
  if (bullet_sim_directory && fs::is_directory(fs::path(*bullet_sim_directory) / "models", ec)) {
    return (fs::path(*bullet_sim_directory) / "models").string();
  }
  return fs::is_directory(BULLET_SIM_SOURCE_MODELS, ec) ? BULLET_SIM_SOURCE_MODELS : "";
}

}  // namespace

PackageResolver PackageResolver::fromEnvironment() {
  std::vector<std::string> path;
  const char* env = std::getenv("ROS_PACKAGE_PATH");
  std::stringstream entries(env ? env : "");
  for (std::string entry; std::getline(entries, entry, ':');) {
    if (!entry.empty()) path.push_back(entry);
  }
  return PackageResolver(std::move(path), GazeboEnvironment::fromEnvironment());
}

PackageResolver::PackageResolver(std::vector<std::string> search_path, GazeboEnvironment gazebo)
    : search_path_(std::move(search_path)), gazebo_environment_(std::move(gazebo)) {}

std::optional<std::string> PackageResolver::packageDirectory(const std::string& package) const {
  auto cached = found_.find(package);
  if (cached != found_.end()) return cached->second;
  std::optional<std::string> result;
  for (const auto& root : search_path_) {
    // The usual layout first (<root>/<package>), so large roots such as /usr/share are not crawled.
    std::error_code ec;
    const fs::path direct = fs::path(root) / package;
    if (fs::exists(direct / "package.xml", ec) && manifestName(direct) == package) {
      result = fs::canonical(direct, ec).string();
    } else {
      crawl(root, kMaxCrawlDepth, [&](const fs::path& dir) {
        if (manifestName(dir) == package) result = fs::canonical(dir, ec).string();
        return result.has_value();
      });
    }
    if (result) break;
  }
  found_[package] = result;
  return result;
}

std::optional<std::string> PackageResolver::resolve(const std::string& uri, std::string* error) const {
  const std::string package_scheme = "package://";
  const std::string model_scheme = "model://";
  const std::string file_scheme = "file://";
  if (uri.rfind(file_scheme, 0) == 0) return uri.substr(file_scheme.size());
  if (uri.rfind(model_scheme, 0) == 0) {
    // model:///x/y is model://x/y, as Gazebo's boost paths join it.
    const size_t start = uri.find_first_not_of('/', model_scheme.size());
    const std::string relative =
        fs::path(uri.substr(std::min(start, uri.size()))).lexically_normal().string();
    std::string why;
    if (auto found = gazeboPaths().findModelFile(relative, &why)) return found;
    if (error) *error = why;  // it names the model, which says more than the whole URI
    return std::nullopt;
  }
  if (uri.rfind(package_scheme, 0) != 0) return uri;

  const std::string rest = uri.substr(package_scheme.size());
  const std::string package = rest.substr(0, rest.find('/'));
  const std::string relative = rest.size() > package.size() ? rest.substr(package.size() + 1) : "";
  if (auto dir = packageDirectory(package)) return (fs::path(*dir) / relative).string();

  if (error) {
    std::string searched;
    for (const auto& root : search_path_) searched += (searched.empty() ? "" : ":") + root;
    *error =
        "cannot resolve [" + uri + "]: no package [" + package + "] in ROS_PACKAGE_PATH [" + searched +
        "]; source your workspace's setup.bash, or add the package's parent directory to ROS_PACKAGE_PATH";
  }
  return std::nullopt;
}

void PackageResolver::forEachPackage(const std::function<void(const std::string& directory)>& visit) const {
  std::set<std::string> seen;
  for (const auto& root : search_path_) {
    crawl(root, kMaxCrawlDepth, [&](const fs::path& dir) {
      const std::optional<std::string> name = manifestName(dir);
      std::error_code ec;
      if (name && seen.insert(*name).second) visit(fs::canonical(dir, ec).string());
      return false;
    });
  }
}

const GazeboPaths& PackageResolver::gazeboPaths() const {
  if (!gazebo_paths_) {
    std::vector<GazeboExports> exports;
    forEachPackage([&](const std::string& directory) { exports.push_back(readGazeboExports(directory)); });
    const std::optional<std::string> bullet_sim = packageDirectory("bullet_sim");
    // bullet_sim's own folder stands where Gazebo's media folder does: worlds/empty.world is ours.
    gazebo_paths_.emplace(gazebo_environment_, exports, shippedModels(bullet_sim), bullet_sim.value_or(""));
  }
  return *gazebo_paths_;
}

}  // namespace bullet_sim
