// Adding a plugin is adding a folder. A scratch copy of this package gets a throwaway plugin folder
// (fixtures/throwaway_plugin) and nothing else; it is configured with static libraries, and the core, bench,
// scenario, render_model and urdf_doctor are built, reusing the suite's objects through ccache (the copy
// mirrors the workspace's layout, so that every compile line but the new plugin's is the suite's). Each
// tool then lists the registry with the plugin in it, the registry's folders are the copy's plugins/, and a
// scenario spawns a robot carrying the plugin, steps it and reads its scans. Slow: about 90 s.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <set>
#include <sstream>

#include "test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;

/// The scratch workspace: the package copied where the workspace keeps it, built where it builds it.
struct Scratch {
  fs::path root = fs::path(BUILD_TOP) / "plugin_folder_scratch";
  fs::path source = root / SOURCE_IN_WORKSPACE;
  fs::path build = root / BUILD_IN_WORKSPACE;
  fs::path devel = root / DEVEL_IN_WORKSPACE;
};

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

/// Runs `command` with ccache relating paths to `root`, as the workspace's build does to the workspace.
test::CommandResult runIn(const fs::path& root, const std::string& command) {
  return test::run("CCACHE_BASEDIR=" + quoted(root) + " CCACHE_NOHASHDIR=true " + command + " 2>&1");
}

/// The folders each line of a registry listing names ("folder filename [sensor types]").
std::set<std::string> listedFolders(const std::string& listing) {
  std::set<std::string> folders;
  std::istringstream lines(listing);
  for (std::string folder, rest; lines >> folder && std::getline(lines, rest);) folders.insert(folder);
  return folders;
}

std::set<std::string> subfolders(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_directory()) names.insert(entry.path().filename().string());
  }
  return names;
}

class PluginFolderBuild : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const Scratch scratch;
    fs::remove_all(scratch.root);
    fs::create_directories(scratch.source.parent_path());
    fs::copy(PACKAGE_DIR, scratch.source, fs::copy_options::recursive);
    const fs::path fixture = fs::path(PACKAGE_DIR) / "test/fixtures/throwaway_plugin";
    fs::create_directories(scratch.source / "plugins/throwaway");
    for (const char* file : {"throwaway.h", "throwaway.cpp"})
      fs::copy_file(fixture / file, scratch.source / "plugins/throwaway" / file);
    configured_ = runIn(scratch.root, "cmake -S " + quoted(scratch.source) + " -B " + quoted(scratch.build) +
                                          " -DBUILD_SHARED_LIBS=OFF -DCATKIN_ENABLE_TESTING=OFF"
                                          " -DCMAKE_BUILD_TYPE=" BUILD_TYPE " -DCATKIN_DEVEL_PREFIX=" +
                                          quoted(scratch.devel) + " -DCMAKE_CXX_COMPILER_LAUNCHER=ccache");
    if (configured_.status != 0) return;
    built_ = runIn(scratch.root, "make -C " + quoted(scratch.build) +
                                     " -j2 bench scenario render_model urdf_doctor");
  }

  void SetUp() override {
    ASSERT_EQ(configured_.status, 0) << configured_.output;
    ASSERT_EQ(built_.status, 0) << built_.output;
  }

  static fs::path tool(const char* name) { return Scratch().devel / "lib/bullet_sim" / name; }

  static test::CommandResult configured_, built_;
};

test::CommandResult PluginFolderBuild::configured_;
test::CommandResult PluginFolderBuild::built_;

TEST_F(PluginFolderBuild, EveryToolListsTheNewFolderAndExactlyTheFoldersUnderPlugins) {
  const std::set<std::string> folders = subfolders(Scratch().source / "plugins");
  ASSERT_EQ(folders.count("throwaway"), 1u);
  std::string first;
  for (const char* name : {"bench", "scenario", "render_model", "urdf_doctor"}) {
    const test::CommandResult listed = test::run(quoted(tool(name)) + " --list-plugins");
    ASSERT_EQ(listed.status, 0) << name << ": " << listed.errors;
    EXPECT_NE(listed.output.find("throwaway libtest_throwaway.so\n"), std::string::npos) << name;
    EXPECT_EQ(listedFolders(listed.output), folders) << name;
    if (first.empty()) first = listed.output;
    EXPECT_EQ(listed.output, first) << name << " lists another registry than bench";
  }
}

TEST_F(PluginFolderBuild, ARobotCarryingItSpawnsStepsAndIsHeardThroughItsTypedOutput) {
  const Scratch scratch;
  const fs::path fixture = scratch.source / "test/fixtures/throwaway_plugin";
  const fs::path out = scratch.root / "scenario_out";
  const test::CommandResult run = test::run(
      quoted(tool("scenario")) + " " + quoted(fixture / "throwaway_scenario.yaml") + " --out " + quoted(out));
  ASSERT_EQ(run.status, 0) << run.output << run.errors;
  const nlohmann::json result = nlohmann::json::parse(test::readFile((out / "result.json").string()));
  // The plugin publishes three beams of 1.25 m: the lidar check read them.
  EXPECT_DOUBLE_EQ(result["metrics"]["throwaway_robot"]["min_lidar_range_m"].get<double>(), 1.25);
}

}  // namespace
}  // namespace bullet_sim
