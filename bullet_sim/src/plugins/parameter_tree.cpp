#include "bullet_sim/plugins/parameter_tree.h"

#include <yaml-cpp/yaml.h>

#include <optional>
#include <sstream>

#include "bullet_sim/common/diagnostics.h"

namespace bullet_sim {

struct ParameterTree::Node {
  YAML::Node yaml;
};

namespace {

std::vector<std::string> keysOf(const std::string& path) {
  std::vector<std::string> keys;
  std::istringstream in(path);
  for (std::string key; std::getline(in, key, '/');) {
    if (!key.empty()) keys.push_back(key);
  }
  return keys;
}

/// The node as a T, or nullopt when it is not one.
template <class T>
std::optional<T> converted(const YAML::Node& node) {
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
}

std::string describeNode(const YAML::Node& node) {
  if (node.IsScalar()) return "[" + node.Scalar() + "]";
  return node.IsSequence() ? "a list" : node.IsMap() ? "a map" : "nothing";
}

}  // namespace

ParameterTree::ParameterTree() = default;

ParameterTree::ParameterTree(std::shared_ptr<const Node> node, std::string source, std::string prefix)
    : node_(std::move(node)), source_(std::move(source)), prefix_(std::move(prefix)) {}

ParameterTree ParameterTree::fromYaml(const std::string& text, const std::string& source) {
  try {
    return ParameterTree(std::make_shared<const Node>(Node{YAML::Load(text)}), source, "");
  } catch (const YAML::Exception& error) {
    throw SpecError(source, {"line " + std::to_string(error.mark.line + 1) + " column " +
                             std::to_string(error.mark.column + 1) + ": " + error.msg});
  }
}

std::shared_ptr<const ParameterTree::Node> ParameterTree::find(const std::string& path) const {
  if (!node_) return nullptr;
  YAML::Node node;
  node.reset(node_->yaml);  // reset() rebinds; assignment would write into the tree
  for (const auto& key : keysOf(path)) {
    if (!node.IsMap()) return nullptr;
    const YAML::Node next = static_cast<const YAML::Node&>(node)[key];  // const: looking up adds nothing
    if (!next) return nullptr;
    node.reset(next);
  }
  return std::make_shared<const Node>(Node{node});
}

bool ParameterTree::has(const std::string& path) const { return find(path) != nullptr; }

ParameterTree ParameterTree::at(const std::string& path) const {
  return ParameterTree(find(path), source_, prefix_ + path + "/");
}

std::vector<std::string> ParameterTree::keys() const {
  std::vector<std::string> keys;
  if (!node_ || !node_->yaml.IsMap()) return keys;
  for (const auto& entry : node_->yaml) keys.push_back(entry.first.as<std::string>());
  return keys;
}

void ParameterTree::wrongKind(const std::string& path, const std::string& kind) const {
  throw SpecError(source_, {prefix_ + path + " must be " + kind + ", not " + describe(path)});
}

std::string ParameterTree::describe(const std::string& path) const {
  const auto found = find(path);
  return found ? describeNode(found->yaml) : "nothing";
}

double ParameterTree::number(const std::string& path, double fallback) const {
  const auto found = find(path);
  if (!found) return fallback;
  if (const auto value = converted<double>(found->yaml)) return *value;
  wrongKind(path, "a number");
}

bool ParameterTree::flag(const std::string& path, bool fallback) const {
  const auto found = find(path);
  if (!found) return fallback;
  if (const auto value = converted<bool>(found->yaml)) return *value;
  wrongKind(path, "true or false");
}

std::string ParameterTree::text(const std::string& path, const std::string& fallback) const {
  const auto found = find(path);
  if (!found) return fallback;
  if (!found->yaml.IsScalar()) wrongKind(path, "a text");
  return found->yaml.Scalar();
}

std::vector<double> ParameterTree::numbers(const std::string& path) const {
  const auto found = find(path);
  if (!found) return {};
  if (auto values = converted<std::vector<double>>(found->yaml)) return std::move(*values);
  wrongKind(path, "a list of numbers");
}

std::vector<ParameterTree> ParameterTree::items(const std::string& path) const {
  const auto found = find(path);
  if (!found) return {};
  if (!found->yaml.IsSequence()) wrongKind(path, "a list");
  std::vector<ParameterTree> items;
  for (size_t i = 0; i < found->yaml.size(); ++i) {
    items.push_back(ParameterTree(std::make_shared<const Node>(Node{found->yaml[i]}), source_,
                                  prefix_ + path + "[" + std::to_string(i) + "]/"));
  }
  return items;
}

std::vector<std::string> ParameterTree::texts(const std::string& path) const {
  const auto found = find(path);
  if (!found) return {};
  if (found->yaml.IsScalar()) return {found->yaml.Scalar()};
  if (auto values = converted<std::vector<std::string>>(found->yaml)) return std::move(*values);
  wrongKind(path, "a name or a list of names");
}

}  // namespace bullet_sim
