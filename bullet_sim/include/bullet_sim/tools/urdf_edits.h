// Edits tools make to a robot description before reading it: the wheel model a run asks for.
#pragma once

#include <string>

namespace bullet_sim {

/// The URDF with <wheelModel> set to `wheel_model` in each drive plugin (diff drive, skid steer, Ackermann);
/// `drives`, when given, counts them. Text that is not XML is returned as it is, for parseModel to report.
std::string withWheelModel(const std::string& urdf, const std::string& wheel_model, int* drives = nullptr);

}  // namespace bullet_sim
