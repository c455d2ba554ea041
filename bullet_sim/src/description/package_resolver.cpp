#include "bullet_sim/description/package_resolver.h"

#include <tinyxml2.h>

#include <cstdlib>
#include <filesystem>
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
// one.
std::optional<std::string> crawl(const fs::path& dir, const std::string& package, int depth) {
  std::error_code ec;
  if (fs::exists(dir / "CATKIN_IGNORE", ec)) return std::nullopt;
  if (fs::exists(dir / "package.xml", ec)) {
    if (manifestName(dir) == package) return fs::canonical(dir, ec).string();
    return std::nullopt;
  }
  if (depth == 0) return std::nullopt;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_directory(ec) || it->path().filename().string().front() == '.') continue;
    if (auto found = crawl(it->path(), package, depth - 1)) return found;
  }
  return std::nullopt;
}

}  // namespace

PackageResolver PackageResolver::fromEnvironment() {
  std::vector<std::string> path;
  const char* env = std::getenv("ROS_PACKAGE_PATH");
  std::stringstream entries(env ? env : "");
  for (std::string entry; std::getline(entries, entry, ':');) {
    if (!entry.empty()) path.push_back(entry);
  }
  return PackageResolver(std::move(path));
}

PackageResolver::PackageResolver(std::vector<std::string> search_path)
    : search_path_(std::move(search_path)) {}

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
      result = crawl(root, package, kMaxCrawlDepth);
    }
    if (result) break;
  }
  found_[package] = result;
  return result;
}

std::optional<std::string> PackageResolver::resolve(const std::string& uri, std::string* error) const {
  const std::string package_scheme = "package://";
  const std::string file_scheme = "file://";
  if (uri.rfind(file_scheme, 0) == 0) return uri.substr(file_scheme.size());
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

}  // namespace bullet_sim
