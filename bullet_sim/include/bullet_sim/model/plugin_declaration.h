// A <plugin>, on its own or inside a <sensor>, as a typed declaration: read and checked once, at load. The
// plugin registry (plugins layer) supplies the config parsers through PluginParsers; this layer holds only
// their results, so it depends on no plugin.
#pragma once

#include <Eigen/Geometry>

#include <memory>
#include <optional>
#include <set>
#include <string>

#include "bullet_sim/common/limits.h"
#include "bullet_sim/model/plugin_tags.h"

namespace bullet_sim {

struct ModelSpec;

/// What every plugin's config starts with, which the plugin registry reads before the plugin's own parser
/// (the parse head). Each plugin derives its own config, with its tags' defaults and units.
struct PluginConfig {
  virtual ~PluginConfig() = default;
  std::string robot_namespace;  ///< <robotNamespace>; a spawn's namespace overrides it
  double update_rate = 0;       ///< [Hz]; 0 = every step
  /// A sensor's link and its pose there, from its <gazebo reference> and <pose>; a model plugin that sits on
  /// a link (an IMU's <bodyName>) sets them itself.
  std::string link;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// Frames written with a leading '/' (global: tf::resolve gives them no tf_prefix), without it.
  std::set<std::string> global_frames;
};

/// A <sensor> inside <gazebo reference="link">.
struct SensorDeclaration {
  std::string name;
  std::string type;                                        ///< "ray", "gpu_ray", "imu", ...
  std::string link;                                        ///< the reference link
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the link frame
  double update_rate = 0;                                  ///< [Hz]; 0 = every step
};

struct PluginDeclaration {
  std::string name;                            ///< the <plugin name="...">
  std::string filename;                        ///< e.g. libgazebo_ros_diff_drive.so
  std::optional<SensorDeclaration> sensor;     ///< set for the plugin of a <sensor>
  std::shared_ptr<const PluginConfig> config;  ///< typed and checked

  /// The sensor's name for a sensor's plugin, else the plugin's: it names the plugin and seeds its noise.
  const std::string& displayName() const { return sensor ? sensor->name : name; }
  /// "plugin [name]", or "sensor [name] on link [link]": the head of every message about it.
  std::string where() const;
  /// The config as `Config`, or nullptr when it is another plugin's.
  template <class Config>
  const Config* configAs() const {
    return dynamic_cast<const Config*>(config.get());
  }
};

/// What a config parser reads: the declaration so far, its tags and the model's links and joints.
struct DeclarationSource {
  const PluginDeclaration& declaration;
  PluginTags& tags;        ///< the <plugin>'s own tags
  const TagNode* sensor;   ///< the <sensor> element; nullptr for a model plugin
  const ModelSpec& model;  ///< its links and joints are complete, its plugins are not
  Diagnostics& diagnostics;
  const Limits& limits;  ///< counts (a lidar's rays, a camera's pixels) above these are errors
};

/// The link that frame tag `tag`, read as `frame`, names. When it names none, a warning says so and that the
/// messages carry `frame` as their frame_id all the same, as Gazebo's do; `fallback` is returned, and named
/// in the warning as the link measured instead unless it is "".
std::string frameLink(const DeclarationSource& source, const std::string& tag, const std::string& frame,
                      const std::string& fallback = "");
/// The same, for a reader with no DeclarationSource: `where` heads the warning.
std::string frameLink(const ModelSpec& model, const std::string& where, const std::string& tag,
                      const std::string& frame, const std::string& fallback, Diagnostics& diagnostics);

/// A <sensor>'s <update_rate> [Hz] as Gazebo's sensor takes it: one below 0 is 0, every step
/// (Sensor::SetUpdateRate sets a period only for a rate above 0), with a warning naming it; `where` heads it.
double sensorUpdateRate(double hz, const std::string& where, Diagnostics& diagnostics);

/// Turns declarations into typed configs; the plugin registry implements it.
class PluginParsers {
 public:
  virtual ~PluginParsers() = default;
  /// The config; nullptr, after one warning, when bullet_sim does not simulate the declaration. Problems
  /// with its tags go to `source.diagnostics`.
  virtual std::shared_ptr<const PluginConfig> parse(const DeclarationSource& source) const = 0;
  /// Checks what the model's plugins ask of it together (two drives on one robot) and adds what they declare
  /// about its joints (a mimic plugin's coupling), once every declaration has its config. Problems go to
  /// `diagnostics`.
  virtual void completeModel(ModelSpec&, Diagnostics&) const {}
};

}  // namespace bullet_sim
