// What this process has cost so far, for bench and the simulator's start-up line: its age, CPU time and
// memory.
#pragma once

#include <optional>

namespace bullet_sim {

/// Seconds since this process was started (exec), from /proc/self/stat: the kernel's clock-tick resolution
/// (10 ms). Nullopt when /proc cannot tell.
std::optional<double> processAge();

/// CPU seconds this process and the children it waited for (xacro, world and mesh readers) have used so far,
/// user and system.
double cpuSeconds();

/// The most resident memory this process has had so far [MB].
double peakRssMb();

/// The resident memory of this process now [MB], from /proc/self/statm; 0 when /proc cannot tell.
double currentRssMb();

}  // namespace bullet_sim
