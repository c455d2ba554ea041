#include "plugins/force_based_move_copies/force_based_move_copies.h"

#include "bullet_sim/plugins/registry.h"

namespace bullet_sim {

namespace {

/// hector's tags and ridgeback's command timeout.
TagTable ridgebackTags() {
  TagTable table = forceBasedMoveTags();
  table.add({"cmdVelTimeOut", TagType::kPositive, "0.25", "s",
             "the robot is driven to rest once cmd_vel has been silent this long", ""});
  return table;
}

/// ridgeback's tags with nexus' default gains, and its caps.
TagTable nexusTags() {
  TagTable table = ridgebackTags();
  const auto row = [](const std::string& tag, const std::string& fallback, const std::string& unit,
                      const std::string& what, const std::string& ours) {
    return TagRow{tag, TagType::kPositive, fallback, unit, what, ours};
  };
  for (const TagRow& added : std::vector<TagRow>{
           row("x_velocity_p_gain", "15", "N s/m",
               "the force along the base's x per m/s of velocity error", ""),
           row("y_velocity_p_gain", "15", "N s/m",
               "the force along the base's y per m/s of velocity error", ""),
           row("yaw_velocity_p_gain", "1", "N m s",
               "the torque about the world's z per rad/s of turn error", ""),
           row("max_x_velocity", "0.6", "m/s",
               "the most of linear.x followed (a negative one is not capped)", ""),
           row("max_y_velocity", "0.6", "m/s",
               "the most of linear.y followed (a negative one is not capped)",
               "nexus' plugin caps linear.y at max_x_velocity; we cap it at max_y_velocity"),
           row("max_yaw_velocity", "0.5", "rad/s",
               "the most of angular.z followed (a negative one is not capped)", ""),
       }) {
    table.add(added);
  }
  return table;
}

}  // namespace

void parseRidgebackForceBasedMove(const DeclarationSource& source, ForceBasedMoveConfig& config) {
  parseForceBasedMove(source, config);
  config.command_timeout = source.tags.nonNegative("cmdVelTimeOut");
}

void parseNexusForceBasedMove(const DeclarationSource& source, ForceBasedMoveConfig& config) {
  parseRidgebackForceBasedMove(source, config);
  PluginTags& tags = source.tags;
  config.command_cap = {tags.nonNegative("max_x_velocity"), tags.nonNegative("max_y_velocity"),
                        tags.nonNegative("max_yaw_velocity")};
}

// The copies that Clearpath's Ridgeback and the Nexus 4WD mecanum robot load.
BULLET_SIM_PLUGIN_FOLDER(force_based_move_copies) {
  registrar.add(pluginType<ForceBasedMove>("libridgeback_ros_force_based_move.so",
                                           parseRidgebackForceBasedMove, ridgebackTags()));
  registrar.add(
      pluginType<ForceBasedMove>("libnexus_ros_force_based_move.so", parseNexusForceBasedMove, nexusTags()));
}

}  // namespace bullet_sim
