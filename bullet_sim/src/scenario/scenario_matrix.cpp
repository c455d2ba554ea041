// Matrix files: a base scenario crossed with axes of values.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "bullet_sim/scenario/scenario_file.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

constexpr long kMaxCells = 1000000;
constexpr long kMaxRange = 100000;

std::string flow(const YAML::Node& node) {
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

std::string fileText(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw ScenarioError(what + " [" + path + "] is not a file");
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// An axis's values: a list, or {from: A, count: N} for the whole numbers A ... A + N - 1 (seeds).
std::vector<std::string> axisValues(const YAML::Node& node, const std::string& where) {
  std::vector<std::string> values;
  if (node.IsSequence()) {
    for (const auto& value : node) values.push_back(flow(value));
  } else if (node.IsMap() && node["from"] && node["count"] && node.size() == 2) {
    long from = 0, count = 0;
    try {
      from = node["from"].as<long>();
      count = node["count"].as<long>();
    } catch (const YAML::Exception&) {
      count = 0;
    }
    if (count < 1 || count > kMaxRange)
      throw ScenarioError(where + ": {from, count} takes whole numbers, count 1 to 100000");
    constexpr long kLargest = std::numeric_limits<long>::max();
    if (from > kLargest - (count - 1))
      throw ScenarioError(where + ": {from: " + std::to_string(from) + ", count: " + std::to_string(count) +
                          "} goes past the largest whole number, " + std::to_string(kLargest));
    for (long i = 0; i < count; ++i) values.push_back(std::to_string(from + i));
  } else {
    throw ScenarioError(where + ": expected a list of values, or {from: A, count: N}");
  }
  if (values.empty()) throw ScenarioError(where + ": has no values");
  return values;
}

/// Puts `value` at the dotted `key` of `root`: maps are made where missing; a number indexes a list.
void setKey(YAML::Node root, const std::string& key, const YAML::Node& value, const std::string& where) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream stream(key);
  while (std::getline(stream, part, '.')) parts.push_back(part);
  YAML::Node current = root;
  for (size_t i = 0; i < parts.size(); ++i) {
    const bool last = i + 1 == parts.size();
    if (current.IsSequence()) {
      size_t index = 0;
      try {
        index = std::stoul(parts[i]);
      } catch (const std::exception&) {
        index = current.size();
      }
      if (index >= current.size())
        throw ScenarioError(where + ": [" + parts[i] + "] is not an index of the list at [" + key + "]");
      if (last) current[index] = value;
      else current.reset(current[index]);
      continue;
    }
    if (!current.IsMap() && !current.IsNull())
      throw ScenarioError(where + ": [" + key + "] goes inside a single value of the scenario");
    if (last) {
      current[parts[i]] = value;
    } else {
      if (!current[parts[i]]) current[parts[i]] = YAML::Node(YAML::NodeType::Map);
      current.reset(current[parts[i]]);
    }
  }
}

}  // namespace

Matrix loadMatrix(const std::string& path) {
  Matrix matrix;
  matrix.source = path;
  matrix.name = fs::path(path).stem().string();
  YAML::Node root;
  try {
    root = YAML::Load(fileText(path, "matrix"));
  } catch (const YAML::Exception& error) {
    throw ScenarioError("matrix " + path + ": not YAML: " + error.what());
  }
  const std::string where = "matrix " + path;
  if (!root.IsMap() || !root["scenario"] || !root["axes"] || !root["axes"].IsMap()) {
    throw ScenarioError(where + ": expected scenario: FILE and axes: {key: [values], ...}");
  }
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (key != "name" && key != "scenario" && key != "axes")
      throw ScenarioError(where + ": unknown key [" + key + "]; expected name, scenario, axes");
  }
  if (root["name"]) matrix.name = root["name"].as<std::string>();
  const fs::path scenario(root["scenario"].as<std::string>());
  matrix.scenario =
      (scenario.is_absolute() ? scenario : fs::absolute(path).parent_path() / scenario).lexically_normal();
  matrix.scenario_yaml = fileText(matrix.scenario, where + ": scenario");
  matrix.count = 1;
  for (const auto& axis : root["axes"]) {
    matrix.axes.push_back(axis.first.as<std::string>());
    matrix.values.push_back(axisValues(axis.second, where + ": axes." + matrix.axes.back()));
    if (static_cast<double>(matrix.count) * matrix.values.back().size() > kMaxCells)
      throw ScenarioError(where + ": more than 1000000 cells");
    matrix.count *= static_cast<int>(matrix.values.back().size());
  }
  return matrix;
}

std::vector<std::pair<std::string, std::string>> Matrix::valuesOf(int index) const {
  if (index < 0 || index >= count) {
    throw ScenarioError("matrix " + source + ": no cell [" + std::to_string(index) + "]: it has " +
                        std::to_string(count) + ", numbered 0 to " + std::to_string(count - 1));
  }
  std::vector<std::pair<std::string, std::string>> picked(axes.size());
  int rest = index;
  for (size_t i = axes.size(); i-- > 0;) {  // the last axis varies fastest
    picked[i] = {axes[i], values[i][rest % values[i].size()]};
    rest /= static_cast<int>(values[i].size());
  }
  return picked;
}

MatrixCell Matrix::cell(int index) const {
  MatrixCell cell;
  cell.index = index;
  cell.values = valuesOf(index);
  YAML::Node root = YAML::Load(scenario_yaml);
  if (!root.IsMap()) throw ScenarioError("scenario " + scenario + ": expected a mapping");
  for (const auto& [axis, value] : cell.values)
    setKey(root, axis, YAML::Load(value), "matrix " + source + ": axes." + axis);
  if (!root["name"]) root["name"] = name;
  root["name"] = root["name"].as<std::string>() + "_" + std::to_string(index);
  YAML::Emitter out;
  out << root;
  cell.yaml = out.c_str();
  return cell;
}

ScenarioSpec cellScenario(const Matrix& matrix, int index, const PackageResolver& resolver) {
  return parseScenario(matrix.cell(index).yaml, matrix.scenario, resolver);
}

}  // namespace bullet_sim
