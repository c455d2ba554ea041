// The `simulator` node: a headless Bullet-backed stand-in for gzserver with gazebo_ros.
#include <ros/ros.h>

#include <iostream>

#include "simulator_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "simulator");
  try {
    bullet_sim::SimulatorNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    node.run();
  } catch (const std::exception& e) {
    // rosconsole may not flush before exit; the user must see why the simulator stopped.
    std::cerr << "simulator: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
