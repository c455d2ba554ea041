#include "bullet_sim/scenario/scenario_command.h"

#include <cmath>
#include <filesystem>

#include "tools/command_line.h"

namespace bullet_sim {

ScenarioCommand parseScenarioCommand(int argc, char** argv) {
  ScenarioCommand command;
  using Value = const std::string&;
  const auto whole = [](Value text, const std::string& option, double high) {
    const double number = parseNumber(text, option);
    if (number < 0 || number > high || number != std::floor(number))
      throw UsageError(option + " [" + text + "]: give a whole number from 0");
    return number;
  };
  const auto bag = [&]() -> BagSettings& { return command.bag ? *command.bag : command.bag.emplace(); };
  const ToolOption file{"file", [&](Value value) {
                          if (!command.file.empty()) throw UsageError("give one scenario FILE");
                          command.file = value;
                        }};
  parseCommandLine(
      argc, argv,
      {{"--out", [&](Value value) { command.out = value; }},
       {"--seed",
        [&](Value v) { command.seed = static_cast<uint64_t>(whole(v, "--seed", 9007199254740992.0)); }},
       {"--matrix", [&](Value value) { command.matrix = value; }},
       {"--index", [&](Value value) { command.index = static_cast<int>(whole(value, "--index", 1e6)); }},
       {"--video", [&](Value) { command.video = true; }, false, /*flag=*/true},
       {"--bag", [&](Value) { bag(); }, false, /*flag=*/true},
       {"--bag-topics", [&](Value value) { bag().topics.push_back(value); }, /*repeatable=*/true},
       {"--bag-compression", [&](Value value) { bag().compression = value; }},
       {"--bag-chunk-size",
        [&](Value v) { bag().chunk_size = static_cast<uint32_t>(whole(v, "--bag-chunk-size", 1 << 30)); }},
       {"--list", [&](Value) { command.list = true; }, false, /*flag=*/true}},
      &command.help, &file);
  if (command.help) return command;
  if (command.matrix.empty() == command.file.empty())
    throw UsageError("give a scenario FILE, or --matrix M.yaml --index N");
  if (!command.matrix.empty() && !command.index && !command.list)
    throw UsageError("--matrix needs --index N (the cell to run), or --list");
  if (command.index && command.matrix.empty()) throw UsageError("--index goes with --matrix");
  if (command.list && command.matrix.empty()) throw UsageError("--list goes with --matrix");
  if (!command.out.empty() && std::filesystem::exists(command.out) &&
      !std::filesystem::is_directory(command.out))
    throw UsageError("--out [" + command.out + "] is a file, not a folder");
  return command;
}

std::vector<std::string> scenarioArguments(const ScenarioCommand& command) {
  std::vector<std::string> words;
  if (!command.file.empty()) words.push_back(command.file);
  if (!command.matrix.empty()) words.insert(words.end(), {"--matrix", command.matrix});
  if (command.index) words.insert(words.end(), {"--index", std::to_string(*command.index)});
  if (command.seed) words.insert(words.end(), {"--seed", std::to_string(*command.seed)});
  if (!command.out.empty()) words.insert(words.end(), {"--out", command.out});
  if (command.video) words.push_back("--video");
  if (command.bag) {
    words.insert(words.end(), {"--bag", "--bag-compression", command.bag->compression, "--bag-chunk-size",
                               std::to_string(command.bag->chunk_size)});
    for (const auto& topic : command.bag->topics) words.insert(words.end(), {"--bag-topics", topic});
  }
  return words;
}

std::optional<BagSettings> bagSettings(const ScenarioCommand& command, const std::string& out) {
  if (!command.bag) return std::nullopt;
  BagSettings settings = *command.bag;
  settings.path = std::filesystem::absolute(std::filesystem::path(out) / "run.bag").string();
  return settings;
}

ScenarioSpec commandScenario(const ScenarioCommand& command, const PackageResolver& resolver,
                             RunContext* context) {
  ScenarioSpec spec;
  if (command.matrix.empty()) {
    spec = loadScenario(command.file, resolver);
  } else {
    const Matrix matrix = loadMatrix(command.matrix);
    const MatrixCell cell = matrix.cell(*command.index);
    spec = parseScenario(cell.yaml, matrix.scenario, resolver);
    context->matrix = {{command.matrix, cell.index}};
    context->matrix_values = cell.values;
  }
  if (command.seed) spec.seed = *command.seed;
  return spec;
}

std::string outputFolder(const ScenarioCommand& command, const ScenarioSpec* spec) {
  if (!command.out.empty()) return command.out;
  if (spec) return "scenario_out/" + spec->name;
  // A scenario that could not be read: named after its file, or its matrix and cell.
  const std::string file = command.matrix.empty() ? command.file : command.matrix;
  const std::string stem = std::filesystem::path(file).stem().string();
  return "scenario_out/" + stem + (command.index ? "_" + std::to_string(*command.index) : "");
}

}  // namespace bullet_sim
