// Gazebo's model path (model://) and resource path (worlds/..., media/...), as gzserver started by gazebo_ros
// builds them, without ROS or Gazebo. Nothing is ever fetched from Gazebo's online model database.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

/// Gazebo's environment variables.
struct GazeboEnvironment {
  std::vector<std::string> model_path;     ///< GAZEBO_MODEL_PATH (':'-separated), searched first
  std::vector<std::string> resource_path;  ///< GAZEBO_RESOURCE_PATH, searched first
  std::string home;                        ///< $HOME: ~/.gazebo/models ends the model path; "" leaves it out

  static GazeboEnvironment fromEnvironment();
};

/// What one package.xml exports to Gazebo, as turtlebot3_gazebo does:
/// `<export><gazebo_ros gazebo_model_path="${prefix}/models" gazebo_media_path="${prefix}"/></export>`.
struct GazeboExports {
  std::vector<std::string> model_path;
  std::vector<std::string> media_path;
};

/// The gazebo_ros exports of the package in `package_dir`, with ${prefix} replaced by that directory.
GazeboExports readGazeboExports(const std::string& package_dir);

/// The folders Gazebo searches, in order.
class GazeboPaths {
 public:
  /// `exports` in package search order; `shipped_models` is bullet_sim's own models folder ("" for none);
  /// `shipped_media` stands where Gazebo's own media folder stands on its resource path (bullet_sim's package
  /// folder, whose worlds/ are Gazebo's worlds/ here; "" for none).
  GazeboPaths(const GazeboEnvironment& environment, const std::vector<GazeboExports>& exports,
              const std::string& shipped_models, const std::string& shipped_media = "");

  /// GAZEBO_MODEL_PATH, the packages' gazebo_model_path exports, bullet_sim's models, ~/.gazebo/models.
  const std::vector<std::string>& modelPath() const { return model_path_; }
  /// GAZEBO_RESOURCE_PATH, then the shipped media (as Gazebo's setup.sh puts its own media folder after the
  /// variable's folders), then the packages' gazebo_media_path exports.
  const std::vector<std::string>& resourcePath() const { return resource_path_; }

  /// The file or folder `relative` ("NAME" or "NAME/meshes/x.dae", from model://NAME/...) in the first model
  /// path folder that has it. nullopt, with `error` naming the model, the folders searched and how to add a
  /// model, when none has it.
  std::optional<std::string> findModelFile(const std::string& relative, std::string* error) const;

  /// The names of the model folders on the model path, for suggestions.
  std::vector<std::string> modelNames() const;

 private:
  std::vector<std::string> model_path_;
  std::vector<std::string> resource_path_;
};

/// The SDF file that the model.config of `model_dir` names: among its <sdf version="..."> elements the
/// highest version that libsdformat reads, as Gazebo picks it. nullopt, with `error` saying what is wrong
/// with the folder and how to fix it, when there is no model.config or it names no existing file.
std::optional<std::string> modelSdfFile(const std::string& model_dir, std::string* error);

}  // namespace bullet_sim
