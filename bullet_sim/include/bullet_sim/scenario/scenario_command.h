// The command line of `scenario`, which its launch scenarios' simulator (scenario_host) shares: which
// scenario (a file, or a matrix's cell), its seed, and where its outputs go.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/scenario/scenario_run.h"
#include "bullet_sim/scenario/scenario_file.h"
#include "bullet_sim/tools/run_recorder.h"

namespace bullet_sim {

struct ScenarioCommand {
  std::string file;                 ///< the scenario file, or "" with --matrix
  std::string matrix;               ///< the matrix file
  std::optional<int> index;         ///< its cell
  std::optional<uint64_t> seed;     ///< overrides the scenario's
  std::string out;                  ///< "" = scenario_out/<name>
  bool video = false;
  /// --bag (or any --bag-* option): a rosbag of the run, DIR/run.bag; its path is set by bagSettings.
  std::optional<BagSettings> bag;
  bool list = false;  ///< with --matrix alone: print the matrix's cells as JSON
  bool help = false;
};

/// Parses the command line; UsageError (tools/command_line.h) says what is wrong.
ScenarioCommand parseScenarioCommand(int argc, char** argv);

/// The words that give `command` again (for scenario_host), without --list and --help.
std::vector<std::string> scenarioArguments(const ScenarioCommand& command);

/// The bag the command asks for, written into the run's folder `out`; nullopt without --bag.
std::optional<BagSettings> bagSettings(const ScenarioCommand& command, const std::string& out);

/// The scenario the command names, its seed applied, and what result.json says about where it came from.
ScenarioSpec commandScenario(const ScenarioCommand& command, const PackageResolver& resolver,
                             RunContext* context);

/// The folder a run writes to: --out, else scenario_out/<name> (`spec` null: the scenario could not be read,
/// and the folder is named after its file, or its matrix and cell).
std::string outputFolder(const ScenarioCommand& command, const ScenarioSpec* spec);

}  // namespace bullet_sim
