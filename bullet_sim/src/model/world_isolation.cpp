// loadWorld, parseWorld and readSdfModel: libsdformat reads the SDF in a child process, which sends the
// WorldSpec back as bytes (world_spec.h says why).
#include "bullet_sim/model/world.h"
#include "assets/byte_codec.h"
#include "assets/child_process.h"
#include "model/description_fields.h"

namespace bullet_sim {

namespace {

constexpr size_t kWorldParseMemory = size_t{8} << 30;  // [bytes] beyond this process's: 3,000 distinct models

/// The child's answer: the warnings, then the world or the problems.
std::string encode(const WorldSpec* world, const std::vector<std::string>& problems,
                   const std::vector<std::string>& warnings) {
  ByteWriter out;
  out(warnings, world != nullptr);
  if (world) {
    out(*world);
  } else {
    out(problems);
  }
  return out.take();
}

WorldSpec decode(const std::string& bytes, const std::string& source, std::vector<std::string>* warnings) {
  ByteReader in(bytes);
  std::vector<std::string> said;
  bool read = false;
  in(said, read);
  if (warnings) warnings->insert(warnings->end(), said.begin(), said.end());
  if (!read) {
    std::vector<std::string> problems;
    in(problems);
    throw SpecError(source, problems);
  }
  WorldSpec world;
  in(world);
  return world;
}

/// Runs `load` in a child process, and hands back what it read or the problems it found.
template <class Load>
WorldSpec loadInChild(const std::string& source, const Load& load, std::vector<std::string>* warnings,
                      const Limits& limits) {
  const ChildOutcome outcome = runInChild(
      [&] {
        std::vector<std::string> said;
        try {
          const WorldSpec world = load(&said);
          return encode(&world, {}, said);
        } catch (const SpecError& e) {
          return encode(nullptr, e.problems(), said);
        }
      },
      kWorldParseMemory, limits.world_load_seconds);
  switch (outcome.ending) {
    case ChildOutcome::Ending::kReturned:
      return decode(outcome.output, source, warnings);
    case ChildOutcome::Ending::kThrew:
      throw SpecError(source, {"reading the SDF failed: " + outcome.why});
    case ChildOutcome::Ending::kCrashed:
      throw SpecError(source, {"libsdformat crashed reading the SDF, with " + outcome.why +
                               ": the file is corrupt, or sdformat cannot read it; check it with gz sdf -k"});
    case ChildOutcome::Ending::kTimedOut:
      throw SpecError(source, {"reading the SDF took longer than " +
                               std::to_string(static_cast<int>(limits.world_load_seconds)) +
                               " s (world_load_seconds): is it that large?"});
    case ChildOutcome::Ending::kNotRun:
      break;
  }
  throw SpecError(source, {"cannot read the SDF: " + outcome.why});
}

}  // namespace

WorldSpec loadWorld(const std::string& path, const PackageResolver& resolver,
                    std::vector<std::string>* warnings, const WorldOptions& options) {
  return loadInChild(
      path, [&](std::vector<std::string>* said) { return loadWorldHere(path, resolver, said, options); },
      warnings, options.limits);
}

WorldSpec parseWorld(const std::string& sdf_text, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings, const WorldOptions& options) {
  return loadInChild(
      source,
      [&](std::vector<std::string>* said) {
        return parseWorldHere(sdf_text, source, resolver, said, options);
      },
      warnings, options.limits);
}

WorldModelSpec readSdfModel(const std::string& sdf_text, const std::string& source,
                            const PackageResolver& resolver, std::vector<std::string>* warnings,
                            const Limits& limits) {
  WorldSpec holder = loadInChild(
      source,
      [&](std::vector<std::string>* said) {
        WorldSpec world;
        world.models.push_back(readSdfModelHere(sdf_text, source, resolver, said, limits));
        return world;
      },
      warnings, limits);
  return std::move(holder.models.front());
}

}  // namespace bullet_sim
