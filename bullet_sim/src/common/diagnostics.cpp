#include "bullet_sim/common/diagnostics.h"

#include <algorithm>
#include <cctype>

namespace bullet_sim {

namespace {

std::string joinProblems(const std::string& source, const std::vector<std::string>& problems) {
  std::string text =
      source + ": " + std::to_string(problems.size()) + (problems.size() == 1 ? " problem" : " problems");
  for (const auto& problem : problems) text += "\n  - " + problem;
  return text;
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

}  // namespace

void Diagnostics::throwIfErrors() const {
  if (!errors_.empty()) throw SpecError(source_, errors_);
}

SpecError::SpecError(const std::string& source, const std::vector<std::string>& problems)
    : std::runtime_error(joinProblems(source, problems)), problems_(problems) {}

std::string closestName(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, name.size() / 4) + 1;  // a few edits, relative to the name
  for (const auto& candidate : candidates) {
    if (lower(candidate) == lower(name)) return candidate;
    const size_t distance = editDistance(lower(name), lower(candidate));
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

std::string didYouMean(const std::string& name, const std::vector<std::string>& candidates) {
  const std::string best = closestName(name, candidates);
  return best.empty() ? "" : " (did you mean [" + best + "]?)";
}

}  // namespace bullet_sim
