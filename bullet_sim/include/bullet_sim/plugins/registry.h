// The one table of what bullet_sim simulates. Each Gazebo plugin filename (for a sensor's plugin, with the
// sensor types it serves) maps to its tag table, its config parser and its factory. A plugin is one folder
// under plugins/ whose BULLET_SIM_PLUGIN_FOLDER function registers its types; the build finds the folders and
// calls each once for the built-in registry. Tests and library users may add their own types to a copy.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/plugins/plugin_checks.h"

namespace bullet_sim {

/// How the registry reads a plugin's update rate, as part of the parse head, before the plugin's parser runs.
struct RateRule {
  enum class From {
    kParser,                ///< the plugin's parser sets it (a control period, hector's rule)
    kTags,                  ///< the first of `tags` present, else `fallback`
    kSensor,                ///< the <sensor>'s <update_rate>; `tags` are read and ignored
    kTagsOverSensor,        ///< the first of `tags` present, else the sensor's
    kSlowerOfSensorAndTags  ///< the plugin's tag throttles the sensor: the slower of the two wins
  };
  From from = From::kParser;
  std::vector<std::string> tags;  ///< in order of precedence
  double fallback = 0;            ///< [Hz] when no tag gives it (kTags)
};

/// How a drive pushes its robot forward along its x, for tools that drive a robot at a speed (bench
/// --strikes).
struct Traction {
  std::vector<std::string> wheels;  ///< the joints of the wheels that push
  double torque = 0;                ///< [N m] the most each of them gets
  double wheel_radius = 0;          ///< [m]
  double acceleration = 0;          ///< [m/s^2] how fast the drive lets its speed change; 0: at once
  double max_speed = std::numeric_limits<double>::infinity();  ///< [m/s] the drive's cap on linear.x
};

/// What a drive plugin drives, for the tools that drive a robot (bench) and urdf_doctor's check of mirrored
/// wheels, which leaves a drive's own wheels to the drive's check.
struct DrivenJoints {
  bool drive = false;  ///< it moves the robot and publishes its odometry: a robot has one drive at most
  /// Wheels sent one sign per side, which must turn about the robot's +y to go forward (empty when the plugin
  /// finds each wheel's sign itself).
  std::vector<std::string> left_wheels;
  std::vector<std::string> right_wheels;
  std::string base_frame;                 ///< the frame the wheels' directions are judged in
  /// A drive's, when it follows a cmd_vel (its Twist input) with wheels of its own.
  std::optional<Traction> traction;
};

/// What decides a robot's wheel-ground model, for a plugin that has a say in it.
struct WheelModelQuery {
  const ModelSpec& model;
  const std::string& robot_name;
  const std::optional<std::string>& robot_namespace;  ///< spawn_model's -robot_namespace
  const ParameterSource* parameters;                   ///< the parameter server's, or nullptr
  Diagnostics& diagnostics;
};

/// What the registry read before the plugin's own parser: the namespace, a sensor's link and pose, and the
/// update rate unless its rule leaves that to the parser.
struct ParseHead {
  std::string robot_namespace;
  std::optional<double> update_rate;  ///< [Hz]
  bool sensor = false;                ///< then `link` and `pose` are the sensor's
  std::string link;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();

  /// Sets in `config` what the head read; the rest keeps the config's own defaults.
  void applyTo(PluginConfig& config) const;
};

using ConfigParser =
    std::function<std::shared_ptr<PluginConfig>(const DeclarationSource& source, const ParseHead& head)>;
using PluginFactory =
    std::function<std::unique_ptr<Plugin>(const PluginDeclaration& declaration, const PluginSetup& setup)>;

struct PluginType {
  std::string filename;                   ///< Gazebo's, e.g. libgazebo_ros_diff_drive.so
  std::vector<std::string> sensor_types;  ///< the <sensor type>s it serves; empty for a model plugin
  /// Every tag it reads, the head's (robotNamespace, the rate's tags) first once registered; its parser reads
  /// through it (PluginTags::useTable).
  TagTable tags;
  RateRule rate;
  unsigned needs = 0;  ///< the Need flags of what it takes from the world at spawn (PluginSetup)
  TfPrefixRule tf_prefix = TfPrefixRule::kSearched;  ///< how its frames take a tf_prefix
  ConfigParser parse;  ///< reads its own tags; the registry then warns once about each other tag
  PluginFactory create;
  /// What it drives (empty for most plugins).
  std::function<DrivenJoints(const PluginDeclaration& declaration)> driven;
  /// The wheel-ground model it asks for its robot, or nullopt when it has no say (most plugins).
  std::function<std::optional<std::string>(const PluginDeclaration& declaration,
                                           const WheelModelQuery& query)>
      wheel_model;
  /// urdf_doctor's check of a plugin of this type (empty for most plugins).
  PluginCheck check;
  /// The joint it makes follow another, and how (a mimic joint plugin), or nullopt (most plugins).
  std::function<std::optional<std::pair<std::string, JointSpec::Mimic>>(const PluginDeclaration& declaration)>
      mimic;
  std::string folder;  ///< the folder under plugins/ that registered it
};

/// A plugin type whose config `Config` is filled by `parse` after the registry's head, and whose behaviour is
/// `Behaviour`, built as Behaviour(declaration, config, setup).
template <class Behaviour, class Config>
PluginType pluginType(std::string filename, void (*parse)(const DeclarationSource&, Config&), TagTable tags) {
  PluginType type;
  type.filename = std::move(filename);
  type.tags = std::move(tags);
  type.parse = [parse](const DeclarationSource& source, const ParseHead& head) {
    auto config = std::make_shared<Config>();
    head.applyTo(*config);
    parse(source, *config);
    return config;
  };
  type.create = [](const PluginDeclaration& declaration,
                   const PluginSetup& setup) -> std::unique_ptr<Plugin> {
    return std::make_unique<Behaviour>(declaration, *declaration.configAs<Config>(), setup);
  };
  return type;
}

class PluginRegistry final : public PluginParsers {
 public:
  /// Every plugin bullet_sim ships: one type or more per folder under plugins/.
  static const PluginRegistry& builtin();

  /// Adds a type (its tag table gains the head's rows); one of the same filename and sensor types is
  /// replaced. A rate tag its table documents as other than TagType::kRate (kIgnored where the sensor's
  /// <update_rate> rules) is a std::logic_error.
  void add(PluginType type);
  /// The type for a model plugin (`sensor_type` nullptr) or a sensor's plugin, or nullptr.
  const PluginType* find(const std::string& filename, const std::string* sensor_type) const;
  /// The type that parsed `declaration`, or nullptr.
  const PluginType* typeOf(const PluginDeclaration& declaration) const;
  const std::vector<PluginType>& types() const { return types_; }
  /// One line per type, sorted: "folder filename [sensor types]", for `--list-plugins`.
  std::string listing() const;

  /// The typed config, or nullptr after one warning when no type matches.
  std::shared_ptr<const PluginConfig> parse(const DeclarationSource& source) const override;
  /// A robot has at most one drive; a mimic plugin's coupling replaces the follower's <mimic>.
  void completeModel(ModelSpec& model, Diagnostics& diagnostics) const override;
  /// The plugin of a declaration this registry parsed.
  std::unique_ptr<Plugin> create(const PluginDeclaration& declaration, const PluginSetup& setup) const;
  /// The wheel-ground model its plugins ask for the robot, or nullopt when none has a say.
  std::optional<std::string> wheelModel(const WheelModelQuery& query) const;

 private:
  std::vector<PluginType> types_;
};

/// What a plugin folder's registration function adds its types through: it stamps them with the folder.
class PluginRegistrar {
 public:
  PluginRegistrar(PluginRegistry& registry, std::string folder)
      : registry_(registry), folder_(std::move(folder)) {}
  void add(PluginType type);

 private:
  PluginRegistry& registry_;
  std::string folder_;
};

/// The registration function of the plugin folder plugins/<folder>: define it (inside namespace bullet_sim)
/// in one of the folder's sources, with a body that adds its types to `registrar`.
#define BULLET_SIM_PLUGIN_FOLDER(folder) void registerPluginFolder_##folder(PluginRegistrar& registrar)

/// Caps a config's update rate at the limit (Gazebo takes any rate), with a warning naming both.
void capUpdateRate(PluginConfig& config, const DeclarationSource& source);

/// parseModel with the built-in plugins.
ModelSpec parseModel(const std::string& urdf_xml, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings = nullptr, const Limits& limits = Limits(),
                     bool strict = false);

}  // namespace bullet_sim
