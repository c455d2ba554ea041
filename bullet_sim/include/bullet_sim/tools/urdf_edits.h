// Edits tools make to a robot description before reading it: the wheel model a run asks for, a plugin's tag.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace bullet_sim {

/// The URDF with <wheelModel> set to `wheel_model` in each drive plugin (diff drive, skid steer, Ackermann);
/// `drives`, when given, counts them. Text that is not XML is returned as it is, for parseModel to report.
std::string withWheelModel(const std::string& urdf, const std::string& wheel_model, int* drives = nullptr);

/// The URDF with tag `tag(filename)` (none when "") set to `text` in each <gazebo> plugin whose filename is
/// one of `filenames`; `plugins`, when given, counts the plugins changed. Text that is not XML is returned as
/// it is.
std::string withPluginTag(const std::string& urdf, const std::vector<std::string>& filenames,
                          const std::function<std::string(const std::string& filename)>& tag,
                          const std::string& text, int* plugins = nullptr);

/// The URDF with the <limit effort> of each joint in `joints` set to `effort` (a <limit> is added where there
/// is none). Text that is not XML is returned as it is.
std::string withEffortLimit(const std::string& urdf, const std::vector<std::string>& joints, double effort);

}  // namespace bullet_sim
