// SDF models to spawn (spawn_sdf_model), read with libsdformat into the same ModelSpec a URDF gives: links
// with their inertia, collisions and visuals, joints, and sensors and plugins through the plugin registry.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/model/model.h"
#include "bullet_sim/model/world.h"

namespace bullet_sim {

/// Parses <sdf><model>...</model></sdf> (as spawn_sdf_model receives it, or a model.sdf file's text) with its
/// plugins typed by `plugins`, libsdformat reading it in a child process (readSdfModel). Throws SpecError
/// naming `source` and every problem, also a value beyond `limits`. Where SDF says more than a URDF can:
/// links joined to nothing are an error (welded to the root in a static model); joints to the world hang
/// their links from a root link named `world`, which fixes the model where it is put (as a URDF's root link
/// `world` does), while its other joints move; a joint whose frame is away from its child link's origin puts
/// that link's frame at the joint, with a warning. Links and collisions keep their SDF names
/// (ModelSpec::names_from_sdf).
ModelSpec parseSdfModel(const std::string& sdf_xml, const std::string& source,
                        const PackageResolver& resolver, const PluginParsers& plugins,
                        std::vector<std::string>* warnings = nullptr, const Limits& limits = Limits());

/// The ModelSpec of a model readSdfModel read (or of a world's non-static model), its problems in
/// `diagnostics`; counts, masses, inertias and joint values beyond `limits` are errors. With
/// `weld_unjoined` (a world's model), links joined to nothing are welded to the root with a warning, not
/// refused.
ModelSpec toModelSpec(const WorldModelSpec& model, const PluginParsers& plugins, Diagnostics& diagnostics,
                      const Limits& limits = Limits(), bool weld_unjoined = false);

}  // namespace bullet_sim
