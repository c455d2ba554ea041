// Robots' own renamed copies of the force-based move plugin, which their descriptions load instead of
// hector's: libridgeback_ros_force_based_move.so (ridgeback_gazebo_plugins) and
// libnexus_ros_force_based_move.so (nexus_4wd_mecanum_gazebo). Both push the base as hector's does
// (force_based_move) and add cmdVelTimeOut: the robot stops once cmd_vel has been silent that long. Nexus'
// copy has its own default gains and caps the command at max_x_velocity, max_y_velocity and max_yaw_velocity.
// Their tag tables are ridgebackTags() and nexusTags() in force_based_move_copies.cpp.
#pragma once

#include "plugins/force_based_move/force_based_move.h"

namespace bullet_sim {

void parseRidgebackForceBasedMove(const DeclarationSource& source, ForceBasedMoveConfig& config);
void parseNexusForceBasedMove(const DeclarationSource& source, ForceBasedMoveConfig& config);

}  // namespace bullet_sim
