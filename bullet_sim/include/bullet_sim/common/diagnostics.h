// Problems found while loading a spec: all of a file's problems are collected, then reported together.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace bullet_sim {

/// Collects the errors and warnings of one load. Messages say where (file, element), what, and the fix. A
/// strict load (~strict_models, urdf_doctor) takes what Gazebo forgives silently for an error.
class Diagnostics {
 public:
  explicit Diagnostics(std::string source, bool strict = false)
      : source_(std::move(source)), strict_(strict) {}

  void error(const std::string& message) { errors_.push_back(message); }
  void warning(const std::string& message) { warnings_.push_back(message); }
  /// What Gazebo forgives without a word: a warning, or an error when the load is strict.
  void forgiven(const std::string& message) { strict_ ? error(message) : warning(message); }
  bool strict() const { return strict_; }

  const std::string& source() const { return source_; }
  const std::vector<std::string>& errors() const { return errors_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// Throws SpecError listing every error, if there is any.
  void throwIfErrors() const;

 private:
  std::string source_;
  bool strict_ = false;
  std::vector<std::string> errors_;
  std::vector<std::string> warnings_;
};

/// A spec that cannot be loaded. what() names the source and lists every problem, one per line.
class SpecError : public std::runtime_error {
 public:
  SpecError(const std::string& source, const std::vector<std::string>& problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

/// The candidate closest to `name` when it is a plausible typo (case or a few edits), else "".
std::string closestName(const std::string& name, const std::vector<std::string>& candidates);

/// " (did you mean [x]?)" for a near miss, else "".
std::string didYouMean(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace bullet_sim
