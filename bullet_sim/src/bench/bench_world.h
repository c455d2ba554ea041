// bench's figures of scale and footprint: a world of many boxes, what loading a world costs, and whether the
// memory of a deleted robot comes back.
#pragma once

#include <string>

#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

/// A file under $TMPDIR (or /tmp) holding `text`, removed with the object. Throws Failure when it cannot be
/// written.
class TemporaryFile {
 public:
  TemporaryFile(const std::string& text, const std::string& suffix);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// A world of n x n static boxes of 0.3 x 0.3 x 0.5 m, 1 m apart, and Gazebo's ground plane, as SDF text. The
/// grid spans x from -n/2 to n/2 m, and its nearest row lies `clearance` [m] to the right (-y) of the origin,
/// so a robot at the origin turning left drives clear of it and its lidar sees it.
std::string boxWorld(int n, double clearance);

/// What loading a world costs, as the simulator node pays it before its first /clock.
struct WorldLoad {
  double load_s = 0;        ///< reading the file into a WorldSpec
  double first_step_s = 0;  ///< and then building the simulation and stepping it once
  double rss_mb = 0;        ///< this process's resident memory after that step
};
/// Reads `world_file` into `world` (as loadWorld does, with its `warnings` and `options`) and measures it:
/// the world is read once, so a bench's startup_s carries one reading, as the node's does.
WorldLoad measureWorldLoad(const std::string& world_file, const PackageResolver& resolver, WorldSpec& world,
                           std::vector<std::string>* warnings, const WorldOptions& options);

/// The resident memory of a simulation of `world` before `model` is first spawned, and after it was spawned,
/// run for 0.5 s (its lidars scan) and deleted `cycles` times, each time giving freed memory back
/// (malloc_trim, as the node does) [MB].
struct DeleteCycle {
  double rss_before_mb = 0;
  double rss_after_mb = 0;
};
DeleteCycle measureDeleteCycle(const WorldSpec& world, const ModelSpec& model, const SpawnPose& pose,
                               int cycles);

}  // namespace bullet_sim
