// A plugin is one folder under plugins/: the built-in registry holds exactly the folders there, every type
// names the folder that registered it, and every executable was built with the same registry.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <sstream>

#include "bullet_sim/plugins/registry.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;

std::set<std::string> pluginFolders() {
  std::set<std::string> folders;
  for (const auto& entry : fs::directory_iterator(PLUGINS_DIR)) {
    if (entry.is_directory()) folders.insert(entry.path().filename().string());
  }
  return folders;
}

TEST(PluginFolders, TheRegistryHoldsExactlyTheFoldersUnderPlugins) {
  std::set<std::string> registered;
  for (const PluginType& type : PluginRegistry::builtin().types()) registered.insert(type.folder);
  const std::set<std::string> folders = pluginFolders();
  EXPECT_GE(folders.size(), 15u);  // the drives, sensors and ros_control bullet_sim ships
  EXPECT_EQ(registered, folders);
}

TEST(PluginFolders, EveryGazeboFilenameWeAcceptIsRegisteredOnce) {
  std::set<std::string> keys;
  for (const PluginType& type : PluginRegistry::builtin().types()) {
    std::string key = type.filename;
    for (const auto& sensor : type.sensor_types) key += " " + sensor;
    EXPECT_TRUE(keys.insert(key).second) << key << " is registered twice";
  }
  for (const char* filename :
       {"libgazebo_ros_diff_drive.so", "libgazebo_ros_skid_steer_drive.so", "libgazebo_ros_p3d.so",
        "libgazebo_ros_control.so", "libgazebo_ros_planar_move.so"})
    EXPECT_NE(PluginRegistry::builtin().find(filename, nullptr), nullptr) << filename;
  const std::string ray = "ray";
  EXPECT_NE(PluginRegistry::builtin().find("libgazebo_ros_laser.so", &ray), nullptr);
}

TEST(PluginFolders, EveryExecutableListsTheSameRegistry) {
  const std::string expected = PluginRegistry::builtin().listing();
  for (const char* tool : {SIMULATOR, BENCH, SCENARIO, RENDER_MODEL, URDF_DOCTOR}) {
    const test::CommandResult result = test::run(std::string(tool) + " --list-plugins");
    EXPECT_EQ(result.status, 0) << tool << ": " << result.errors;
    EXPECT_EQ(result.output, expected) << tool;
  }
}

}  // namespace
}  // namespace bullet_sim
