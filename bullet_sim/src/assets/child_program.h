// Running another program (a Python tool) in a child process with bounded memory and wall time, as runInChild
// runs a library: a program that hangs or eats memory ends only itself.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace bullet_sim {

struct ProgramOutcome {
  enum class Ending {
    kExited,    ///< `status` holds its exit status
    kCrashed,   ///< killed by a signal; `why` names it
    kTimedOut,  ///< killed after its time
    kNotRun,    ///< no process could be started; `why` says why
  };
  Ending ending = Ending::kNotRun;
  int status = -1;
  std::string output;  ///< what it wrote on stdout
  std::string errors;  ///< what it wrote on stderr (its first 64 KiB)
  std::string why;
};

/// Runs `command` (its first word an absolute path; no shell, no PATH lookup) with `input` on its stdin,
/// `memory` bytes of address space, no core dump, none of this process's open files, and `seconds` of wall
/// time, after which it is killed. It is killed too when it writes more than `max_output` bytes on stdout,
/// or when this process dies.
ProgramOutcome runProgram(const std::vector<std::string>& command, const std::string& input, size_t memory,
                          double seconds, size_t max_output);

}  // namespace bullet_sim
