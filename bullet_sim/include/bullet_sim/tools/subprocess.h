// Running another program, as the tools and the tests do (xacro above all): one helper for all of them.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

struct ProcessOutput {
  int status = -1;     ///< exit status, or -1 when the program did not exit normally
  std::string output;  ///< what it printed on stdout
  std::string errors;  ///< and on stderr
};

/// Runs `command` (its first word looked up on PATH, no shell) to its end and collects what it prints;
/// nullopt, with `error` set, when it cannot start.
std::optional<ProcessOutput> runProcess(const std::vector<std::string>& command, std::string* error);

/// The URDF that `xacro file args...` prints. Throws std::runtime_error with xacro's own message when it
/// fails, and says how to install xacro when it is missing.
std::string expandXacro(const std::string& file, const std::vector<std::string>& args = {});

}  // namespace bullet_sim
