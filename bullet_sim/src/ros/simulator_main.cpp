// The `simulator` node: a headless Bullet-backed stand-in for gzserver with gazebo_ros. It registers as
// /gazebo, as gzserver does, so that spawn_model and every /gazebo/... client find it without __name:=gazebo.
#include <ros/ros.h>

#include <iostream>

#include "bullet_sim/plugins/registry.h"
#include "exit_guard.h"
#include "master_watch.h"
#include "simulator_node.h"

namespace {
constexpr double kExitGraceSeconds = 1.5;  // after SIGINT: the node must be gone within 2 s
constexpr double kMasterCheckSeconds = 1;
constexpr double kMasterSilenceSeconds = 3;
}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) != "--list-plugins") continue;
    std::cout << bullet_sim::PluginRegistry::builtin().listing();  // what this build simulates
    return 0;
  }
  ros::init(argc, argv, "gazebo", ros::init_options::NoSigintHandler);
  const bullet_sim::ExitGuard guard(kExitGraceSeconds);
  try {
    bullet_sim::SimulatorNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    const bullet_sim::MasterWatch master(kMasterCheckSeconds, kMasterSilenceSeconds);
    node.run();
    if (const auto lost = master.lost()) {
      std::cerr << "simulator: " << *lost << std::endl;
      return 1;
    }
  } catch (const std::exception& e) {
    // rosconsole may not flush before exit; the user must see why the simulator stopped.
    std::cerr << "simulator: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
