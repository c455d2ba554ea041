// Work that may crash, hang or eat memory inside a library we cannot fix (assimp on a hostile file), done in
// a forked child process so that it ends only the child.
#pragma once

#include <functional>
#include <string>

namespace bullet_sim {

struct ChildOutcome {
  enum class Ending {
    kReturned,  ///< `output` holds what the work returned
    kThrew,     ///< `why` holds the exception's message (std::bad_alloc: it ran out of its memory)
    kCrashed,   ///< `why` names the signal
    kTimedOut,  ///< killed after its time
    kNotRun,    ///< no child could be started; `why` says why
  };
  Ending ending = Ending::kNotRun;
  std::string output;
  std::string why;
};

/// Runs `work` in a child process forked from this one, with `extra_memory` bytes of address space beyond
/// what this process has mapped, no core dump, default SIGINT and SIGTERM, and `seconds` of wall time, after
/// which it is killed. The child touches nothing of the parent's but what `work` does, and leaves through
/// _exit. Call it from one thread at a time.
ChildOutcome runInChild(const std::function<std::string()>& work, size_t extra_memory, double seconds);

}  // namespace bullet_sim
