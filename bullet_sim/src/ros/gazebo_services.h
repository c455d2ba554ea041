// The services and topics of gazebo_ros's api plugin, with gazebo_msgs types, under the simulator's private
// namespace (/gazebo): they translate messages to the core's world API (simulation/world_api.h) and back.
//
// Topics: model_states and link_states (published after a step while someone subscribes, at most
//   ~model_states_rate [sim Hz, default 1000; 0 = every step] each), set_model_state and set_link_state (in).
// Services: spawn_urdf_model, spawn_sdf_model, delete_model, get/set_model_state, get/set_link_state,
// get_model_properties,
//   get_world_properties, get_joint_properties, set_joint_properties, get/set_link_properties,
//   set_model_configuration, apply_body_wrench, clear_body_wrenches, apply_joint_effort, clear_joint_forces,
//   get/set_physics_properties, and delete_light and get/set_light_properties, which answer that there are no
//   lights. A request that cannot be honoured answers success false with the reason.
#pragma once

#include <gazebo_msgs/ApplyBodyWrench.h>
#include <gazebo_msgs/ApplyJointEffort.h>
#include <gazebo_msgs/BodyRequest.h>
#include <gazebo_msgs/DeleteLight.h>
#include <gazebo_msgs/DeleteModel.h>
#include <gazebo_msgs/GetJointProperties.h>
#include <gazebo_msgs/GetLightProperties.h>
#include <gazebo_msgs/GetLinkProperties.h>
#include <gazebo_msgs/GetLinkState.h>
#include <gazebo_msgs/GetModelProperties.h>
#include <gazebo_msgs/GetModelState.h>
#include <gazebo_msgs/GetPhysicsProperties.h>
#include <gazebo_msgs/GetWorldProperties.h>
#include <gazebo_msgs/JointRequest.h>
#include <gazebo_msgs/LinkStates.h>
#include <gazebo_msgs/ModelStates.h>
#include <gazebo_msgs/SetJointProperties.h>
#include <gazebo_msgs/SetLightProperties.h>
#include <gazebo_msgs/SetLinkProperties.h>
#include <gazebo_msgs/SetLinkState.h>
#include <gazebo_msgs/SetModelConfiguration.h>
#include <gazebo_msgs/SetModelState.h>
#include <gazebo_msgs/SetPhysicsProperties.h>
#include <gazebo_msgs/SpawnModel.h>
#include <ros/ros.h>

#include <map>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"
#include "bullet_sim/simulation/world_api.h"

namespace bullet_sim {

/// What the world API asks of the node that runs the simulation.
class SimulationHost {
 public:
  virtual ~SimulationHost() = default;
  /// Spawns a robot with its ROS side; throws with the reason, leaving nothing behind.
  virtual Robot& spawnRobot(const std::string& name, ModelSpec model, const SpawnPose& pose,
                            const std::string& robot_namespace, std::vector<std::string>* warnings) = 0;
  /// Deletes a robot and its ROS side; false when there is no robot of that name.
  virtual bool deleteRobot(const std::string& name) = 0;
  virtual bool paused() const = 0;
  /// The physics properties changed: the node paces by the new step and update rate from now on.
  virtual void physicsChanged() = 0;
};

class GazeboServices {
 public:
  GazeboServices(ros::NodeHandle private_node, Simulation& simulation, WorldApi& world, SimulationHost& host);

  /// Publishes model_states and link_states when they are due and someone listens; call after each step.
  void afterStep();

 private:
  bool spawnUrdf(gazebo_msgs::SpawnModel::Request& request, gazebo_msgs::SpawnModel::Response& response);
  /// SDF, and URDF too, as Gazebo's.
  bool spawnSdf(gazebo_msgs::SpawnModel::Request& request, gazebo_msgs::SpawnModel::Response& response);
  bool deleteModel(gazebo_msgs::DeleteModel::Request& request, gazebo_msgs::DeleteModel::Response& response);
  bool getModelState(gazebo_msgs::GetModelState::Request& request,
                     gazebo_msgs::GetModelState::Response& response);
  bool setModelState(gazebo_msgs::SetModelState::Request& request,
                     gazebo_msgs::SetModelState::Response& response);
  bool getLinkState(gazebo_msgs::GetLinkState::Request& request,
                    gazebo_msgs::GetLinkState::Response& response);
  bool setLinkState(gazebo_msgs::SetLinkState::Request& request,
                    gazebo_msgs::SetLinkState::Response& response);
  bool getModelProperties(gazebo_msgs::GetModelProperties::Request& request,
                          gazebo_msgs::GetModelProperties::Response& response);
  bool getWorldProperties(gazebo_msgs::GetWorldProperties::Request& request,
                          gazebo_msgs::GetWorldProperties::Response& response);
  bool getJointProperties(gazebo_msgs::GetJointProperties::Request& request,
                          gazebo_msgs::GetJointProperties::Response& response);
  bool setJointProperties(gazebo_msgs::SetJointProperties::Request& request,
                          gazebo_msgs::SetJointProperties::Response& response);
  bool getLinkProperties(gazebo_msgs::GetLinkProperties::Request& request,
                         gazebo_msgs::GetLinkProperties::Response& response);
  bool setLinkProperties(gazebo_msgs::SetLinkProperties::Request& request,
                         gazebo_msgs::SetLinkProperties::Response& response);
  bool setModelConfiguration(gazebo_msgs::SetModelConfiguration::Request& request,
                             gazebo_msgs::SetModelConfiguration::Response& response);
  bool applyBodyWrench(gazebo_msgs::ApplyBodyWrench::Request& request,
                       gazebo_msgs::ApplyBodyWrench::Response& response);
  bool clearBodyWrenches(gazebo_msgs::BodyRequest::Request& request, gazebo_msgs::BodyRequest::Response&);
  bool applyJointEffort(gazebo_msgs::ApplyJointEffort::Request& request,
                        gazebo_msgs::ApplyJointEffort::Response& response);
  bool clearJointForces(gazebo_msgs::JointRequest::Request& request, gazebo_msgs::JointRequest::Response&);
  bool getPhysicsProperties(gazebo_msgs::GetPhysicsProperties::Request& request,
                            gazebo_msgs::GetPhysicsProperties::Response& response);
  bool setPhysicsProperties(gazebo_msgs::SetPhysicsProperties::Request& request,
                            gazebo_msgs::SetPhysicsProperties::Response& response);
  /// The set_model_state and set_link_state topics: like the services, with a warning instead of an answer.
  void onModelState(const gazebo_msgs::ModelState::ConstPtr& state);
  void onLinkState(const gazebo_msgs::LinkState::ConstPtr& state);
  /// Parses and spawns a request's model: a URDF, or with `sdf_too` SDF as well.
  std::string spawn(const gazebo_msgs::SpawnModel::Request& request, bool sdf_too);
  void advertiseServices();
  void publishStates();

  ros::NodeHandle node_;
  Simulation& simulation_;
  WorldApi& world_;
  SimulationHost& host_;
  std::vector<ros::ServiceServer> services_;
  std::vector<ros::Subscriber> subscribers_;
  ros::Publisher model_states_;
  ros::Publisher link_states_;
  int model_listeners_ = 0;  ///< subscribers of model_states, counted by its connect callbacks
  int link_listeners_ = 0;
  double states_period_ = 0.001;  ///< [sim s] between model_states (and link_states) messages
  double states_due_ = 0;         ///< [sim s] when the next ones may go out
  gazebo_msgs::ODEPhysics ode_;   ///< as last set: reported back, not used
  std::map<std::string, uint32_t> state_requests_;  ///< get_model_state calls per model: the header's seq
};

}  // namespace bullet_sim
