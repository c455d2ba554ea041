// scenario: one run of a scenario file (or of a matrix's cell), judged by its checks. ROS-free: a timeline
// scenario runs in this process; a launch scenario starts a ROS master, the simulator and the user's nodes as
// processes of its own, and stops every one of them. The exit code is the verdict.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/scenario/scenario_command.h"
#include "tools/command_line.h"
#include "scenario/scenario_launch.h"

namespace bullet_sim {
namespace {

constexpr char kUsage[] =
    "usage: scenario FILE.yaml [--out DIR] [--seed N] [--video] [--bag [--bag-topics REGEX]...\n"
    "                [--bag-compression none|lz4|bz2] [--bag-chunk-size BYTES]]\n"
    "       scenario --matrix M.yaml --index N [--out DIR] [--seed N] [--video] [--bag ...]\n"
    "       scenario --matrix M.yaml --list\n"
    "\n"
    "Runs the scenario FILE (or cell N of the matrix M, numbered from 0) and writes into DIR\n"
    "(default scenario_out/<name>): result.json (the verdict, every check's measured value, the\n"
    "RTF, the wall time, the seed and the versions), trajectory.csv (each robot's root link every\n"
    "record_period), top.png (a plan with the trails), with --video, video.mp4 (the chase view) and,\n"
    "with --bag, run.bag: a rosbag in sim time of each robot's ground truth, links, sensors and\n"
    "commands (--bag-topics: regular expressions of the topics to record, default all but images and\n"
    "point clouds; --bag-compression: lz4 by default; --bag-chunk-size: 786432 bytes by default).\n"
    "A timeline scenario runs in this process, without a ROS master, and is deterministic; a launch\n"
    "scenario starts its own master on a free port, the simulator and the launch file, and stops\n"
    "them all when it ends. --seed replaces the scenario's seed. --list prints the matrix's cells\n"
    "as JSON. docs/scenarios.md describes the files.\n"
    "Exit status: 0 every check passed, 1 a check failed, 2 the scenario could not run, or a bad\n"
    "argument or matrix (said in one line).\n";

/// A file's problems, listed one per indented line, as one line: "scenario F: a; b".
std::string oneLine(const std::string& text) {
  std::string line;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\n') {
      line += text[i];
      continue;
    }
    while (i + 1 < text.size() && text[i + 1] == ' ') ++i;
    line += line.empty() || line.back() == ':' ? " " : "; ";
  }
  return line;
}

/// --list: the matrix's size, axes and every cell's values, as JSON on stdout.
int listMatrix(const ScenarioCommand& command) {
  const Matrix matrix = loadMatrix(command.matrix);
  nlohmann::ordered_json json;
  json["name"] = matrix.name;
  json["scenario"] = matrix.scenario;
  json["axes"] = matrix.axes;
  json["count"] = matrix.count;
  json["cells"] = nlohmann::ordered_json::array();
  // The first and the last cell, which take every axis's first and last value, are read as scenarios: a key
  // or a value the scenario refuses there (a seed of -5) is said now; elsewhere, it is that cell's run's
  // error.
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  cellScenario(matrix, 0, resolver);
  cellScenario(matrix, matrix.count - 1, resolver);
  for (int i = 0; i < matrix.count; ++i) {
    nlohmann::ordered_json values = nlohmann::ordered_json::object();
    for (const auto& [axis, value] : matrix.valuesOf(i)) values[axis] = value;
    json["cells"].push_back({{"index", i}, {"values", values}});
  }
  std::cout << json.dump(2) << "\n";
  return 0;
}

/// The run's folder, made before the run: a path that cannot be one is said in one line.
void makeOutputFolder(const std::string& out) {
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) throw std::runtime_error("cannot make the run's folder [" + out + "]: " + error.message());
}

int run(const ScenarioCommand& command) {
  if (command.list) {
    try {
      return listMatrix(command);
    } catch (const std::exception& error) {  // a bad matrix: as bad as a bad argument
      std::cerr << "scenario: " << oneLine(error.what()) << "\n";
      return static_cast<int>(Verdict::kError);
    }
  }
  RunContext context;
  std::optional<ScenarioSpec> spec;
  std::string out = outputFolder(command, nullptr);
  try {
    const PackageResolver resolver = PackageResolver::fromEnvironment();
    spec = commandScenario(command, resolver, &context);
    context.spec = &*spec;
    out = outputFolder(command, &*spec);
    makeOutputFolder(out);
    const Verdict verdict =
        spec->launch ? runLaunch(*spec, command, out)
                     : runTimeline(*spec, context, out, command.video, bagSettings(command, out));
    std::ifstream result(out + "/result.json");
    const auto json = nlohmann::json::parse(result, nullptr, false);
    const std::string message = json.is_object() ? json.value("message", "") : "";
    (verdict == Verdict::kPass ? std::cout : std::cerr)
        << "scenario " << spec->name << ": " << message << " (" << out << "/result.json)\n";
    return static_cast<int>(verdict);
  } catch (const std::exception& error) {
    std::cerr << "scenario: could not run: " << oneLine(error.what()) << "\n";
    try {
      writeErrorResult(out, context, error.what());
    } catch (const std::exception&) {
    }
    return static_cast<int>(Verdict::kError);
  }
}

}  // namespace
}  // namespace bullet_sim

// Not toolMain: a bad argument is one line here (sweep reads it as a cell's reason), and every refusal
// exits 2.
int main(int argc, char** argv) {
  if (bullet_sim::listPlugins(argc, argv)) return EXIT_SUCCESS;
  bullet_sim::ScenarioCommand command;
  try {
    command = bullet_sim::parseScenarioCommand(argc, argv);
  } catch (const bullet_sim::UsageError& error) {
    std::cerr << "scenario: " << error.what() << " (scenario --help lists the arguments)\n";
    return 2;
  }
  if (command.help) {
    std::cout << bullet_sim::kUsage;
    return EXIT_SUCCESS;
  }
  return bullet_sim::run(command);
}
