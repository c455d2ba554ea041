#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <stdexcept>

namespace bullet_sim {

/// Calls every plugin folder's registration function (builtin_plugins.cpp, which the build writes).
void registerBuiltinPlugins(PluginRegistry& registry);

namespace {

/// The head's rows, which every type's table starts with.
TagTable headTable(const PluginType& type) {
  TagTable head{{"robotNamespace", TagType::kText, "", "",
                 "the ROS namespace of the plugin's topics, services and frames' prefix",
                 "spawn_model's -robot_namespace replaces it, as gazebo_ros's does"}};
  const bool sensor_rate = type.rate.from == RateRule::From::kSensor;
  for (const std::string& tag : type.rate.tags) {
    if (type.tags.row(tag)) continue;  // the plugin documents it itself
    head.add({tag, sensor_rate ? TagType::kIgnored : TagType::kRate,
              type.rate.from == RateRule::From::kTags ? std::to_string(type.rate.fallback) : "the sensor's",
              "Hz", "how often the plugin publishes (0: every step)",
              sensor_rate ? "the sensor's <update_rate> rules" : ""});
  }
  for (const TagRow& row : type.tags.rows()) head.add(row);
  return head;
}

/// The parse head: namespace, rate, and a sensor's link and pose, read for every plugin alike.
ParseHead readHead(const PluginType& type, const DeclarationSource& source) {
  PluginTags& tags = source.tags;
  ParseHead head;
  head.robot_namespace = tags.text("robotNamespace", "");
  const double sensor_rate = source.declaration.sensor ? source.declaration.sensor->update_rate : 0.0;
  if (const auto& sensor = source.declaration.sensor) {
    head.sensor = true;
    head.link = sensor->link;
    head.pose = sensor->pose;
  }
  std::optional<double> tag_rate;
  for (const std::string& tag : type.rate.tags) {
    if (type.rate.from == RateRule::From::kSensor || !tags.has(tag))
      continue;  // ignored rows: nothing to read
    const double value = tags.rate(tag, 0);
    if (!tag_rate) tag_rate = value;
  }
  switch (type.rate.from) {
    case RateRule::From::kParser: break;
    case RateRule::From::kTags: head.update_rate = tag_rate.value_or(type.rate.fallback); break;
    case RateRule::From::kSensor: head.update_rate = sensor_rate; break;
    case RateRule::From::kTagsOverSensor: head.update_rate = tag_rate.value_or(sensor_rate); break;
    case RateRule::From::kSlowerOfSensorAndTags:
      head.update_rate = sensor_rate;
      if (tag_rate && *tag_rate > 0 && (sensor_rate == 0 || *tag_rate < sensor_rate))
        head.update_rate = *tag_rate;
      break;
  }
  return head;
}

}  // namespace

void ParseHead::applyTo(PluginConfig& config) const {
  config.robot_namespace = robot_namespace;
  if (update_rate) config.update_rate = *update_rate;
  if (sensor) {
    config.link = link;
    config.pose = pose;
  }
}

const PluginRegistry& PluginRegistry::builtin() {
  static const PluginRegistry registry = [] {
    PluginRegistry built;
    registerBuiltinPlugins(built);
    return built;
  }();
  return registry;
}

void PluginRegistry::add(PluginType type) {
  type.tags = headTable(type);
  // The head reads each rate tag as a rate (below 0: 0, as Gazebo's plugins take it); a row documenting it
  // otherwise would show the reference page a rule the parser does not follow.
  const TagType rate_type = type.rate.from == RateRule::From::kSensor ? TagType::kIgnored : TagType::kRate;
  for (const std::string& tag : type.rate.tags) {
    if (type.tags.row(tag)->type != rate_type) {
      throw std::logic_error(type.filename + "'s rate tag <" + tag + "> is not documented as " +
                             tagTypeName(rate_type) + " in its tag table");
    }
  }
  auto same = std::find_if(types_.begin(), types_.end(), [&](const PluginType& known) {
    return known.filename == type.filename && known.sensor_types == type.sensor_types;
  });
  if (same != types_.end()) {
    *same = std::move(type);
  } else {
    types_.push_back(std::move(type));
  }
}

void PluginRegistrar::add(PluginType type) {
  type.folder = folder_;
  registry_.add(std::move(type));
}

const PluginType* PluginRegistry::find(const std::string& filename, const std::string* sensor_type) const {
  for (const auto& type : types_) {
    if (type.filename != filename) continue;
    const bool serves = sensor_type
                            ? std::count(type.sensor_types.begin(), type.sensor_types.end(), *sensor_type) > 0
                            : type.sensor_types.empty();
    if (serves) return &type;
  }
  return nullptr;
}

const PluginType* PluginRegistry::typeOf(const PluginDeclaration& declaration) const {
  const auto& sensor = declaration.sensor;
  return find(declaration.filename, sensor ? &sensor->type : nullptr);
}

std::string PluginRegistry::listing() const {
  std::vector<std::string> lines;
  for (const PluginType& type : types_) {
    std::string line = type.folder + " " + type.filename;
    for (const std::string& sensor : type.sensor_types) line += " " + sensor;
    lines.push_back(line);
  }
  std::sort(lines.begin(), lines.end());
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

std::shared_ptr<const PluginConfig> PluginRegistry::parse(const DeclarationSource& source) const {
  const PluginDeclaration& declaration = source.declaration;
  if (const PluginType* type = typeOf(declaration)) {
    source.tags.useTable(&type->tags);
    const ParseHead head = readHead(*type, source);
    std::shared_ptr<PluginConfig> config = type->parse(source, head);
    capUpdateRate(*config, source);
    config->global_frames = source.tags.globalFrames();
    source.tags.finish();  // one warning for each tag the parser did not read
    return config;
  }
  if (const auto& sensor = declaration.sensor) {
    source.diagnostics.warning(declaration.where() + " of type [" + sensor->type + "] with plugin [" +
                               declaration.filename + "] is not simulated by bullet_sim: ignored");
  } else {
    source.diagnostics.warning(declaration.where() + " filename [" + declaration.filename +
                               "] is not a plugin bullet_sim simulates: ignored");
  }
  return nullptr;
}

namespace {

/// Each mimic plugin's coupling on its follower, in place of the follower's <mimic>: one coupling drives it.
void applyMimicPlugins(const PluginRegistry& registry, ModelSpec& model, Diagnostics& diagnostics) {
  std::set<std::string> coupled;
  for (const auto& plugin : model.plugins) {
    const PluginType* type = registry.typeOf(plugin);
    if (!type || !type->mimic) continue;
    auto coupling = type->mimic(plugin);
    JointSpec* follower = coupling ? model.joint(coupling->first) : nullptr;
    if (!follower) continue;  // its parser said why
    if (!coupled.insert(follower->name).second) {
      diagnostics.warning(plugin.where() + ": joint [" + follower->name + "] already follows [" +
                          follower->mimic->joint + "] by " + follower->mimic->source +
                          "; this plugin is ignored (two couplings would fight)");
      continue;
    }
    const JointSpec::Mimic& by_plugin = coupling->second;
    // The usual pair (<mimic> for robot_state_publisher, the plugin for Gazebo) agree; say so when they do
    // not.
    if (follower->mimic && (follower->mimic->joint != by_plugin.joint ||
                            follower->mimic->multiplier != by_plugin.multiplier ||
                            follower->mimic->offset != by_plugin.offset)) {
      diagnostics.warning(plugin.where() + " makes joint [" + follower->name + "] follow [" +
                          by_plugin.joint + "] otherwise than its <mimic> of [" + follower->mimic->joint +
                          "] says: the plugin's coupling is the one simulated");
    }
    follower->mimic = by_plugin;
  }
}

}  // namespace

void PluginRegistry::completeModel(ModelSpec& model, Diagnostics& diagnostics) const {
  applyMimicPlugins(*this, model, diagnostics);
  std::vector<const PluginDeclaration*> drives;
  for (const auto& plugin : model.plugins) {
    const PluginType* type = typeOf(plugin);
    if (type && type->driven && type->driven(plugin).drive) drives.push_back(&plugin);
  }
  if (drives.size() > 1) {
    std::string names;
    for (const auto* drive : drives) names += (names.empty() ? "" : " and ") + drive->where();
    diagnostics.error("the robot has " + std::to_string(drives.size()) + " drives, " + names +
                      ": they would fight over its wheels and both publish its odometry; keep one");
  }
}

std::optional<std::string> PluginRegistry::wheelModel(const WheelModelQuery& query) const {
  for (const auto& plugin : query.model.plugins) {
    const PluginType* type = typeOf(plugin);
    if (!type || !type->wheel_model) continue;
    if (auto model = type->wheel_model(plugin, query)) return model;
  }
  return std::nullopt;
}

void capUpdateRate(PluginConfig& config, const DeclarationSource& source) {
  const double limit = source.limits.max_rate;
  if (config.update_rate <= limit) return;
  std::ostringstream message;
  message << source.declaration.where() << ": update rate " << config.update_rate
          << " Hz is above the limit of " << limit << " Hz (max_rate): " << limit
          << " Hz is used (no plugin updates more often than once a step)";
  source.diagnostics.warning(message.str());
  config.update_rate = limit;
}

std::unique_ptr<Plugin> PluginRegistry::create(const PluginDeclaration& declaration,
                                               const PluginSetup& setup) const {
  const PluginType* type = typeOf(declaration);
  if (!type) {
    throw std::invalid_argument(declaration.where() + " filename [" + declaration.filename +
                                "] was parsed by another plugin registry than the simulation's");
  }
  return type->create(declaration, setup);
}

ModelSpec parseModel(const std::string& urdf_xml, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings, const Limits& limits, bool strict) {
  return parseModel(urdf_xml, source, resolver, PluginRegistry::builtin(), warnings, limits, strict);
}

}  // namespace bullet_sim
