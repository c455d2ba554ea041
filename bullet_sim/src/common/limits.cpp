#include "bullet_sim/common/limits.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <variant>

#include "bullet_sim/common/names.h"

namespace bullet_sim {

namespace {

using Field = std::variant<size_t Limits::*, double Limits::*>;

struct NamedLimit {
  const char* name;
  Field field;
};

const NamedLimit kLimits[] = {
    {"max_description_bytes", &Limits::max_description_bytes},
    {"max_links", &Limits::max_links},
    {"max_moving_joints", &Limits::max_moving_joints},
    {"max_shapes", &Limits::max_shapes},
    {"max_world_shapes", &Limits::max_world_shapes},
    {"max_mesh_bytes", &Limits::max_mesh_bytes},
    {"max_triangles", &Limits::max_triangles},
    {"max_rays", &Limits::max_rays},
    {"max_image_pixels", &Limits::max_image_pixels},
    {"max_length", &Limits::max_length},
    {"max_mass", &Limits::max_mass},
    {"max_inertia", &Limits::max_inertia},
    {"mesh_import_seconds", &Limits::mesh_import_seconds},
    {"decomposition_seconds", &Limits::decomposition_seconds},
    {"max_convex_parts", &Limits::max_convex_parts},
    {"world_load_seconds", &Limits::world_load_seconds},
    {"max_effort", &Limits::max_effort},
    {"max_rate", &Limits::max_rate},
};

const NamedLimit* find(const std::string& name) {
  for (const NamedLimit& limit : kLimits) {
    if (name == limit.name) return &limit;
  }
  return nullptr;
}

std::string text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

void Limits::set(const std::string& name, double value) {
  const NamedLimit* limit = find(name);
  if (!limit) {
    std::vector<std::string> known;
    for (const auto& each : kLimits) known.push_back(each.name);
    throw std::invalid_argument("no limit [" + name + "]; the limits are " + joinedNames(known));
  }
  if (!std::isfinite(value) || value <= 0)
    throw std::invalid_argument("limit [" + name + "] must be a positive number, not " + text(value));
  std::visit(
      [&](auto member) {
        using Value = std::remove_reference_t<decltype(this->*member)>;
        if constexpr (std::is_integral_v<Value>) {
          if (value != std::floor(value) || value > 1e15)
            throw std::invalid_argument("limit [" + name + "] must be a whole number up to 1e15, not " +
                                        text(value));
        }
        this->*member = static_cast<Value>(value);
      },
      limit->field);
}

std::vector<std::string> Limits::names() {
  std::vector<std::string> names;
  for (const auto& limit : kLimits) names.emplace_back(limit.name);
  return names;
}

std::optional<double> Limits::get(const std::string& name) const {
  const NamedLimit* limit = find(name);
  if (!limit) return std::nullopt;
  return std::visit([&](auto member) { return static_cast<double>(this->*member); }, limit->field);
}

std::string aboveLimit(double value, const char* name, const Limits& limits, const std::string& unit) {
  const std::string units = unit.empty() ? "" : " " + unit;
  return text(value) + units + " is above the limit of " + text(limits.get(name).value_or(NAN)) + units +
         " (" + name + ")";
}

std::optional<std::string> boundProblem(double value, double bound, const char* limit_name,
                                        const std::string& unit) {
  if (!std::isfinite(value)) return "[" + text(value) + "] is not a finite number";
  if (std::abs(value) > bound) {
    const std::string units = unit.empty() ? "" : " " + unit;
    return "[" + text(value) + "]" + units + " is beyond the limit of " + text(bound) + units + " (" +
           limit_name + ")";
  }
  return std::nullopt;
}

}  // namespace bullet_sim
