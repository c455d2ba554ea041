// What Gazebo's world API (gazebo_ros's api plugin) reads and changes, as plain values: the states of models
// and links, their properties, scheduled wrenches and joint efforts, the physics properties. ROS-free; the
// WorldApi serves them (world_api.h), and the ROS layer only translates messages.
//
// Entity names are Gazebo's: a model ("robot"), a link scoped by its model ("robot::base_link"), or a bare
// link name, meaning the first model (in modelNames() order) that has such a link. Reference frames name an
// entity the same way; "", "world", "map" and "/map" mean the world frame.
#pragma once

#include <Eigen/Geometry>

#include <limits>
#include <string>
#include <vector>

#include "bullet_sim/model/model.h"

namespace bullet_sim {

/// Where an entity is and how it moves, relative to a reference frame.
struct EntityState {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< its frame in the reference frame
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();        ///< [m/s] of its origin, in reference axes
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();       ///< [rad/s] in reference axes
};

/// A model's or a link's world state under its Gazebo name (links scoped: "robot::base_link").
struct NamedState {
  std::string name;
  EntityState state;
};

struct ModelProperties {
  std::vector<std::string> body_names;  ///< its links (a robot's links that fixed joints merge are not links)
  std::vector<std::string> geom_names;  ///< its collisions, named as Gazebo names a URDF's
  std::vector<std::string> joint_names;  ///< its moving joints
  std::vector<std::string> child_model_names;
  bool is_static = false;
};

struct LinkProperties {
  double mass = 0;                                    ///< [kg]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      ///< [m] in the link frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  ///< [kg m^2] about the com, in link axes
  bool gravity = true;
};

struct JointProperties {
  JointSpec::Type type = JointSpec::Type::kRevolute;
  double position = 0;  ///< [rad] or [m]
  double rate = 0;      ///< [rad/s] or [m/s]
  double damping = 0;   ///< [N m s/rad] or [N s/m]
  double lower = -std::numeric_limits<double>::infinity();  ///< [rad] or [m]
  double upper = std::numeric_limits<double>::infinity();
};

/// A time window of sim time, as Gazebo's api plugin schedules wrenches and efforts.
struct Schedule {
  double start_time = 0;  ///< [s]; a time already past means the next step
  double duration = -1;   ///< [s]; < 0 lasts until cleared, 0 does nothing, less than a step lasts one step
};

/// apply_body_wrench: a force and a torque on a link for a while.
struct BodyWrench {
  std::string body;  ///< a link ("robot::link" or a bare name), or a model, meaning its root link
  /// The entity whose axes force, torque and reference_point are given in, as they are when the wrench is
  /// applied for; "" or "world" for the world's.
  std::string reference_frame;
  Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();  ///< [m] where the force acts, from the
                                                              ///< link's centre of mass (Gazebo's)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();            ///< [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();           ///< [N m]
  Schedule schedule;
};

/// apply_joint_effort: an effort on a joint for a while.
struct JointEffort {
  std::string joint;  ///< "robot::joint" or a bare name
  double effort = 0;  ///< [N m] or [N]
  Schedule schedule;
};

struct PhysicsProperties {
  double step_size = 0.001;  ///< [s] of sim time per step
  /// [steps per wall s] the pace whoever runs the simulation keeps (the node); 0 = as fast as possible.
  double max_update_rate = 1000;
  Eigen::Vector3d gravity{0, 0, -9.81};  ///< [m/s^2]
};

}  // namespace bullet_sim
