// The parameters plugins read at run time, as ros_control's controllers read theirs from the parameter
// server: a tree of maps, lists and values (YAML). The ROS node fills one from the parameter server; tools
// that run without ROS (bench, scenarios) read it from a YAML file, e.g. a robot's control.yaml.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace bullet_sim {

class ParameterTree {
 public:
  /// An empty tree: every parameter is absent.
  ParameterTree();

  /// Parses YAML text. Throws SpecError naming `source`, with the line and column of a syntax error.
  static ParameterTree fromYaml(const std::string& text, const std::string& source);

  /// Paths are slash-separated keys, e.g. "diff_drive_controller/linear/x/max_velocity".
  bool has(const std::string& path) const;
  /// The subtree at `path`; an empty tree when it is absent.
  ParameterTree at(const std::string& path) const;
  /// The keys of the map at this tree's root, in the file's order; none when it is not a map.
  std::vector<std::string> keys() const;

  /// The value at `path`, or `fallback` when it is absent. A value of the wrong kind throws SpecError naming
  /// the full path and the value.
  double number(const std::string& path, double fallback) const;
  bool flag(const std::string& path, bool fallback) const;
  std::string text(const std::string& path, const std::string& fallback) const;
  /// A list of numbers; empty when absent.
  std::vector<double> numbers(const std::string& path) const;
  /// One text or a list of texts (ros_controllers take `left_wheel: name` and `left_wheel: [a, b]` alike);
  /// empty when absent.
  std::vector<std::string> texts(const std::string& path) const;
  /// The entries of a list (e.g. joint_state_controller's extra_joints, a list of maps); empty when absent.
  std::vector<ParameterTree> items(const std::string& path) const;
  /// What the value at `path` is, for messages: "[value]", "a list", "a map" or "nothing".
  std::string describe(const std::string& path) const;

  const std::string& source() const { return source_; }

 private:
  struct Node;
  ParameterTree(std::shared_ptr<const Node> node, std::string source, std::string prefix);
  std::shared_ptr<const Node> find(const std::string& path) const;
  [[noreturn]] void wrongKind(const std::string& path, const std::string& kind) const;

  std::shared_ptr<const Node> node_;  ///< nullptr when empty
  std::string source_;
  std::string prefix_;  ///< this tree's path in the whole, for messages ("" at the root)
};

/// Where plugins read their run-time parameters: the ROS parameter server in the node, one tree (a YAML file)
/// in tools and tests.
class ParameterSource {
 public:
  virtual ~ParameterSource() = default;
  /// The parameters under the absolute name `ns` ("/husky_velocity_controller"; "/" for all of them); an
  /// empty tree when there are none. Throws SpecError when they cannot be read.
  virtual ParameterTree fetch(const std::string& ns) const = 0;
};

/// Parameters from one tree, e.g. a robot's control.yaml as `rosparam load` puts it at the root.
class TreeParameters : public ParameterSource {
 public:
  explicit TreeParameters(ParameterTree root) : root_(std::move(root)) {}
  ParameterTree fetch(const std::string& ns) const override { return root_.at(ns); }

 private:
  ParameterTree root_;
};

}  // namespace bullet_sim
