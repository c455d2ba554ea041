// Resolves package:// and model:// URIs through ROS_PACKAGE_PATH and Gazebo's model path, without ROS
// libraries.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/assets/gazebo_paths.h"

namespace bullet_sim {

class PackageResolver {
 public:
  /// Search path from the ROS_PACKAGE_PATH environment variable (':'-separated), Gazebo's from its own.
  static PackageResolver fromEnvironment();
  explicit PackageResolver(std::vector<std::string> search_path, GazeboEnvironment gazebo = {});

  /// Absolute path of a package's directory, or nullopt when no package.xml names it.
  std::optional<std::string> packageDirectory(const std::string& package) const;

  /// "package://pkg/rel/path" -> "<pkg dir>/rel/path"; "model://NAME/rel" -> that file in the first model
  /// path folder holding it ("model://NAME" -> the model's folder); "file:///abs" -> "/abs"; other text is a
  /// plain path. On failure returns nullopt and sets `error` to a message that names the URI, where it was
  /// looked for, and the fix.
  std::optional<std::string> resolve(const std::string& uri, std::string* error) const;

  /// Gazebo's model and resource paths: its environment variables, the gazebo_ros exports of the packages
  /// on the search path, and the models bullet_sim ships. Built when first asked for.
  const GazeboPaths& gazeboPaths() const;

 private:
  /// Calls `visit` with the directory of every package on the search path, once per package name, the
  /// first found winning (as rospack does).
  void forEachPackage(const std::function<void(const std::string& directory)>& visit) const;

  std::vector<std::string> search_path_;
  GazeboEnvironment gazebo_environment_;
  mutable std::map<std::string, std::optional<std::string>> found_;
  mutable std::optional<GazeboPaths> gazebo_paths_;
};

}  // namespace bullet_sim
