// find_model NAME | --path | --list: Gazebo's model path as bullet_sim sees it. NAME prints the SDF file that
// the model.config of model NAME names (what model://NAME means in a world, and what gazebo_ros's
// `spawn_model -database NAME` spawns). ROS-free: it reads GAZEBO_MODEL_PATH, ROS_PACKAGE_PATH (for the
// packages' gazebo_model_path exports) and HOME.
#include <iostream>
#include <string>
#include <vector>

#include "bullet_sim/assets/package_resolver.h"
#include "tools/command_line.h"

namespace bullet_sim {
namespace {

constexpr char kUsage[] =
    "usage: find_model NAME | --path | --list\n"
    "\n"
    "  NAME     prints the SDF file of model NAME, found on Gazebo's model path and picked by its "
    "model.config\n"
    "  --path   prints the model path, one folder a line, in search order: GAZEBO_MODEL_PATH, the\n"
    "           gazebo_model_path exports of the packages on ROS_PACKAGE_PATH, bullet_sim's models,\n"
    "           ~/.gazebo/models\n"
    "  --list   prints the name of every model folder on the model path\n"
    "Exit status: 0 found, 1 no such model (the message says where it looked and how to add one), 2 usage.\n";

struct Options {
  bool help = false;
  bool path = false;
  bool list = false;
  std::string name;
};

Options parse(int argc, char** argv) {
  Options options;
  const ToolOption positional{"NAME", [&](const std::string& word) {
                                if (!options.name.empty())
                                  throw UsageError("one NAME only, not [" + word + "]");
                                options.name = word;
                              }};
  parseCommandLine(argc, argv,
                   {{"--path", [&](const std::string&) { options.path = true; }, false, true},
                    {"--list", [&](const std::string&) { options.list = true; }, false, true}},
                   &options.help, &positional);
  if (!options.help && options.path + options.list + !options.name.empty() != 1) {
    throw UsageError("give one of NAME, --path and --list");
  }
  return options;
}

int run(const Options& options) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  const GazeboPaths& paths = resolver.gazeboPaths();
  if (options.path) {
    for (const auto& folder : paths.modelPath()) std::cout << folder << "\n";
    return 0;
  }
  if (options.list) {
    for (const auto& name : paths.modelNames()) std::cout << name << "\n";
    return 0;
  }
  std::string error;
  const auto folder = paths.findModelFile(options.name, &error);
  const auto file = folder ? modelSdfFile(*folder, &error) : std::nullopt;
  if (!file) throw Failure(error);
  std::cout << *file << "\n";
  return 0;
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  return bullet_sim::toolMain("find_model", bullet_sim::kUsage, argc, argv, bullet_sim::parse,
                              bullet_sim::run);
}
