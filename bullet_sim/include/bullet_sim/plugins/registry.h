// The one table of what bullet_sim simulates. Each Gazebo plugin filename (for a sensor's plugin, with the
// sensor types it serves) maps to its config parser and its factory. A new plugin is one file pair under
// plugins/ and one line in registry.cpp's table; tests and library users may add their own to a copy.
// Beside it, the run-time types: ros_control's controller type names, which load_controller builds by name.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/plugins/ros_control/controller.h"

namespace bullet_sim {

using ConfigParser = std::function<std::shared_ptr<const PluginConfig>(const DeclarationSource& source)>;
using PluginFactory =
    std::function<std::unique_ptr<Plugin>(const PluginDeclaration& declaration, const PluginSetup& setup)>;

struct PluginType {
  std::string filename;                   ///< Gazebo's, e.g. libgazebo_ros_diff_drive.so
  std::vector<std::string> sensor_types;  ///< the <sensor type>s it serves; empty for a model plugin
  ConfigParser parse;  ///< reads the tags it knows; the registry then warns once about each other tag
  PluginFactory create;
};

/// Caps a config's update rate at the limit (Gazebo takes any rate), with a warning naming both.
void capUpdateRate(PluginConfig& config, const DeclarationSource& source);

/// A plugin type whose config `Config` comes from `parse` and whose behaviour is `Behaviour`, built as
/// Behaviour(declaration, config, setup).
template <class Behaviour, class Config>
PluginType pluginType(std::string filename, std::vector<std::string> sensor_types,
                      Config (*parse)(const DeclarationSource&)) {
  return {std::move(filename), std::move(sensor_types),
          [parse](const DeclarationSource& source) {
            Config config = parse(source);
            capUpdateRate(config, source);
            return std::make_shared<const Config>(std::move(config));
          },
          [](const PluginDeclaration& declaration, const PluginSetup& setup) -> std::unique_ptr<Plugin> {
            return std::make_unique<Behaviour>(declaration, *declaration.configAs<Config>(), setup);
          }};
}

class PluginRegistry final : public PluginParsers {
 public:
  /// Every plugin bullet_sim ships.
  static const PluginRegistry& builtin();

  /// Adds a type; one of the same filename and sensor types is replaced.
  void add(PluginType type);
  /// The type for a model plugin (`sensor_type` nullptr) or a sensor's plugin, or nullptr.
  const PluginType* find(const std::string& filename, const std::string* sensor_type) const;

  /// The typed config, or nullptr after one warning when no type matches.
  std::shared_ptr<const PluginConfig> parse(const DeclarationSource& source) const override;
  /// A robot has at most one drive.
  void checkModel(const ModelSpec& model, Diagnostics& diagnostics) const override;
  /// The plugin of a declaration this registry parsed.
  std::unique_ptr<Plugin> create(const PluginDeclaration& declaration, const PluginSetup& setup) const;

 private:
  std::vector<PluginType> types_;
};

using ControllerFactory = std::function<std::unique_ptr<Controller>(const ControllerSetup& setup)>;

struct ControllerType {
  std::string name;  ///< ros_controllers' type name, e.g. diff_drive_controller/DiffDriveController
  ControllerFactory create;
};

/// A controller type built as Behaviour(setup, args...).
template <class Behaviour, class... Args>
ControllerType controllerType(std::string name, Args... args) {
  return {std::move(name), [args...](const ControllerSetup& setup) -> std::unique_ptr<Controller> {
            return std::make_unique<Behaviour>(setup, args...);
          }};
}

class ControllerRegistry {
 public:
  /// Every controller type bullet_sim ships.
  static const ControllerRegistry& builtin();

  /// Adds a type; one of the same name is replaced.
  void add(ControllerType type);
  /// The type of that name, or nullptr.
  const ControllerType* find(const std::string& name) const;
  /// Every type's name, in the table's order.
  std::vector<std::string> names() const;

 private:
  std::vector<ControllerType> types_;
};

/// parseModel with the built-in plugins.
ModelSpec parseModel(const std::string& urdf_xml, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings = nullptr, const Limits& limits = Limits());

}  // namespace bullet_sim
