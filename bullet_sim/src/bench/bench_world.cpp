#include "bench/bench_world.h"

#include <malloc.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "bullet_sim/tools/process_stats.h"
#include "bench/bench_drive.h"
#include "tools/command_line.h"

namespace bullet_sim {

namespace {

constexpr double kBoxSide = 0.3, kBoxHeight = 0.5;  // [m]
constexpr double kSettleSeconds = 0.5;              // [s] a spawned robot runs before it is deleted

}  // namespace

TemporaryFile::TemporaryFile(const std::string& text, const std::string& suffix) {
  const char* tmpdir = std::getenv("TMPDIR");
  path_ = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/bullet_sim_bench_XXXXXX" + suffix;
  const int fd = mkstemps(path_.data(), static_cast<int>(suffix.size()));
  const bool written = fd >= 0 && write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  if (fd >= 0) close(fd);
  if (!written)
    throw Failure("cannot write a temporary file [" + path_ + "]: set TMPDIR to a writable directory");
}

TemporaryFile::~TemporaryFile() { std::remove(path_.c_str()); }

std::string boxWorld(int n, double clearance) {
  std::ostringstream sdf;
  sdf << "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\">\n<world name=\"boxes\">\n"
      << "<include><uri>model://ground_plane</uri></include>\n";
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x = i - n / 2.0 + 0.5, y = -clearance - j;
      sdf << "<model name=\"box_" << i << "_" << j << "\"><static>true</static><pose>" << x << " " << y << " "
          << kBoxHeight / 2 << " 0 0 0</pose><link name=\"link\">"
          << "<collision name=\"collision\"><geometry><box><size>" << kBoxSide << " " << kBoxSide << " "
          << kBoxHeight << "</size></box></geometry></collision>"
          << "<visual name=\"visual\"><geometry><box><size>" << kBoxSide << " " << kBoxSide << " "
          << kBoxHeight << "</size></box></geometry></visual></link></model>\n";
    }
  }
  sdf << "</world>\n</sdf>\n";
  return sdf.str();
}

WorldLoad measureWorldLoad(const std::string& world_file, const PackageResolver& resolver, WorldSpec& world,
                           std::vector<std::string>* warnings, const WorldOptions& options) {
  WorldLoad load;
  const auto start = std::chrono::steady_clock::now();
  world = loadWorld(world_file, resolver, warnings, options);
  load.load_s = secondsSince(start);
  Simulation simulation(world);
  simulation.step();
  load.first_step_s = secondsSince(start);
  load.rss_mb = currentRssMb();
  return load;
}

DeleteCycle measureDeleteCycle(const WorldSpec& world, const ModelSpec& model, const SpawnPose& pose,
                               int cycles) {
  DeleteCycle cycle;
  Simulation simulation(world);
  simulation.step();
  malloc_trim(0);
  cycle.rss_before_mb = currentRssMb();
  for (int i = 0; i < cycles; ++i) {
    simulation.spawn(model.name, model, pose);
    for (int step = 0; step * simulation.stepSize() < kSettleSeconds; ++step) simulation.step();
    simulation.remove(model.name);
    malloc_trim(0);
  }
  cycle.rss_after_mb = currentRssMb();
  return cycle;
}

}  // namespace bullet_sim
