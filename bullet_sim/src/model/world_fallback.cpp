#include <stdexcept>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/world.h"

namespace bullet_sim {

namespace {

/// The world file `name` names, loaded; nullopt, with `problem` saying why, when it cannot be found or read.
std::optional<WorldSpec> tryLoad(const std::string& name, const PackageResolver& resolver,
                                 std::vector<std::string>* warnings, const WorldOptions& options,
                                 std::string* path, std::string* problem) {
  const std::optional<std::string> found = findWorldFile(name, resolver, problem);
  if (!found) return std::nullopt;
  try {
    std::vector<std::string> its_warnings;
    WorldSpec world = loadWorld(*found, resolver, &its_warnings, options);
    if (warnings) warnings->insert(warnings->end(), its_warnings.begin(), its_warnings.end());
    if (path) *path = *found;
    return world;
  } catch (const SpecError& error) {
    if (options.strict_models) throw std::runtime_error(error.what());  // refusals were asked for
    *problem = error.what();  // names the file and lists its problems
    return std::nullopt;
  }
}

}  // namespace

WorldSpec loadWorldOrFallback(const std::string& name, const std::string& fallback,
                              const PackageResolver& resolver, std::vector<std::string>* warnings,
                              const WorldOptions& options, std::string* path) {
  std::string problem;
  if (auto world = tryLoad(name, resolver, warnings, options, path, &problem)) return std::move(*world);
  if (fallback.empty()) throw std::runtime_error("world [" + name + "]: " + problem);
  if (warnings) {
    warnings->push_back("falling back on " + fallback + ", as gzserver does: " + problem);
  }
  std::string fallback_problem;
  if (auto world = tryLoad(fallback, resolver, warnings, options, path, &fallback_problem)) {
    return std::move(*world);
  }
  throw std::runtime_error("world [" + name + "]: " + problem + "; and its fallback [" + fallback +
                           "]: " + fallback_problem);
}

}  // namespace bullet_sim
