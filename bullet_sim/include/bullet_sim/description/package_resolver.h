// Resolves package:// URIs through ROS_PACKAGE_PATH, without ROS libraries.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

class PackageResolver {
 public:
  /// Search path from the ROS_PACKAGE_PATH environment variable (':'-separated).
  static PackageResolver fromEnvironment();
  explicit PackageResolver(std::vector<std::string> search_path);

  /// Absolute path of a package's directory, or nullopt when no package.xml names it.
  std::optional<std::string> packageDirectory(const std::string& package) const;

  /// "package://pkg/rel/path" -> "<pkg dir>/rel/path"; "file:///abs" -> "/abs"; other text is a plain path.
  /// On failure returns nullopt and sets `error` to a message that names the URI and the search path.
  std::optional<std::string> resolve(const std::string& uri, std::string* error) const;

 private:
  std::vector<std::string> search_path_;
  mutable std::map<std::string, std::optional<std::string>> found_;
};

}  // namespace bullet_sim
