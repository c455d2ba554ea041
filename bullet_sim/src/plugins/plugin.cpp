#include "bullet_sim/plugins/plugin.h"

#include <cmath>
#include <sstream>

namespace bullet_sim {

namespace {
// Sim time is a whole number of steps; this absorbs the rounding of k * dt against a period.
constexpr double kTimeEpsilon = 1e-9;
}  // namespace

bool UpdateTimer::wouldFire(const StepTime& time) const { return time.sim_time + kTimeEpsilon >= next_; }

bool UpdateTimer::due(const StepTime& time) {
  if (!wouldFire(time)) return false;
  next_ += period_;
  if (next_ < time.sim_time + kTimeEpsilon) next_ = time.sim_time + period_;  // never fire twice in one step
  return true;
}

PluginTags::PluginTags(const tinyxml2::XMLElement* element, std::string where, Diagnostics& diagnostics)
    : element_(element), where_(std::move(where)), diagnostics_(diagnostics) {}

const tinyxml2::XMLElement* PluginTags::find(const std::string& tag) {
  read_.insert(tag);
  return element_ ? element_->FirstChildElement(tag.c_str()) : nullptr;
}

bool PluginTags::has(const std::string& tag) const {
  return element_ && element_->FirstChildElement(tag.c_str()) != nullptr;
}

std::string PluginTags::text(const std::string& tag, const std::string& fallback) {
  const auto* e = find(tag);
  if (!e) return fallback;
  std::string value = e->GetText() ? e->GetText() : "";
  const auto first = value.find_first_not_of(" \t\n\r");
  const auto last = value.find_last_not_of(" \t\n\r");
  return first == std::string::npos ? "" : value.substr(first, last - first + 1);
}

double PluginTags::number(const std::string& tag, double fallback) {
  if (!has(tag)) {
    read_.insert(tag);
    return fallback;
  }
  const std::string value = text(tag, "");
  std::istringstream in(value);
  double parsed;
  if (!(in >> parsed) || !std::isfinite(parsed)) {
    diagnostics_.error(where_ + " <" + tag + "> must be a number, not [" + value + "]");
    return fallback;
  }
  return parsed;
}

double PluginTags::positive(const std::string& tag, double fallback, bool allow_zero) {
  const double value = number(tag, fallback);
  if (value < 0 || (!allow_zero && value == 0)) {
    std::ostringstream message;
    message << where_ << " <" << tag << "> must be " << (allow_zero ? ">= 0" : "> 0") << ", not " << value;
    diagnostics_.error(message.str());
    return fallback;
  }
  return value;
}

bool PluginTags::flag(const std::string& tag, bool fallback) {
  if (!has(tag)) {
    read_.insert(tag);
    return fallback;
  }
  const std::string value = text(tag, "");
  if (value == "true" || value == "1") return true;
  if (value == "false" || value == "0") return false;
  diagnostics_.error(where_ + " <" + tag + "> must be true or false, not [" + value + "]");
  return fallback;
}

std::vector<std::string> PluginTags::list(const std::string& tag) {
  std::string value = text(tag, "");
  for (char& c : value) {
    if (c == ',') c = ' ';
  }
  std::istringstream in(value);
  std::vector<std::string> items;
  for (std::string item; in >> item;) items.push_back(item);
  return items;
}

void PluginTags::accept(std::initializer_list<const char*> tags) {
  for (const char* tag : tags) read_.insert(tag);
}

void PluginTags::finish() {
  if (!element_) return;
  for (auto* e = element_->FirstChildElement(); e; e = e->NextSiblingElement()) {
    if (!read_.count(e->Name())) {
      diagnostics_.warning(where_ + " <" + std::string(e->Name()) +
                           "> is not a tag this plugin knows: ignored");
      read_.insert(e->Name());  // one warning per tag
    }
  }
}

uint64_t stableHash(const std::string& text) {
  uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace bullet_sim
