// The ROS face of one spawned robot: for every plugin, a subscription per input, a publisher per output and a
// server per service, in the robot's namespace and with its frame prefix. Each output type maps to its
// message, each input type to its subscription and each request type to its service, in one place. Runs between steps, on the node's thread.
#pragma once

#include <image_transport/publisher.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/simulation.h"

namespace camera_info_manager {
class CameraInfoManager;
}

namespace bullet_sim {

/// Frame names as the robot publishes them: without leading or trailing '/', and under the robot's prefix,
/// except the global frames (world, map).
class FramePrefix {
 public:
  explicit FramePrefix(std::string prefix) : prefix_(std::move(prefix)) {}
  std::string operator()(const std::string& frame) const;

 private:
  std::string prefix_;
};

class RobotAdapter {
 public:
  /// `robot_namespace` from the spawn request overrides every plugin's <robotNamespace> when it is not empty;
  /// it is also the frame prefix, which is otherwise the first <robotNamespace> among the robot's plugins.
  /// `sim_time` tells when an input arrived.
  RobotAdapter(Robot& robot, const std::string& robot_namespace, tf2_ros::TransformBroadcaster& tf,
               std::function<double()> sim_time);

  /// Publishes what the plugins produced since the last call, and tells each plugin whether its on-demand
  /// outputs (camera images) have subscribers now.
  void publish();

  /// The topics this robot advertises and subscribes, for the log.
  const std::vector<std::string>& topics() const { return topics_; }

 private:
  struct Output {
    std::function<uint64_t()> count;  ///< changes when the plugin has a new sample
    std::function<void()> publish;
    uint64_t seen = 0;
    Demand* demand = nullptr;  ///< the plugin's, set from the subscriber count
    std::function<uint32_t()> subscribers;
  };
  struct Connection;  ///< what connect() needs of one plugin

  void connect(const Plugin& plugin);
  void advertise(const Connection& plugin, const OutputPort& port);
  void subscribe(const Connection& plugin, const InputPort& port);
  void serve(const Connection& plugin, const ServicePort& port);
  template <class Message, class Sample, class Convert>
  void advertiseStream(const Connection& plugin, const OutputPort& port, const Stream<Sample>* stream,
                       Convert convert);
  /// Images go through image_transport (raw only: Debian has no compressed transport).
  void advertiseImages(const Connection& plugin, const OutputPort& port, const Stream<CameraImage>* stream);
  /// camera_info comes from the camera's camera_info_manager, which serves set_camera_info.
  void advertiseCameraInfo(const Connection& plugin, const OutputPort& port, const Stream<CameraInfo>* stream);
  void broadcast(const Stream<TransformSample>* stream, const FramePrefix& frames);
  ros::NodeHandle handleFor(const std::string& plugin_namespace) const;

  const std::string robot_name_;
  std::string namespace_;
  FramePrefix frames_;
  tf2_ros::TransformBroadcaster& tf_;
  std::function<double()> sim_time_;
  std::vector<ros::Publisher> publishers_;
  std::vector<image_transport::Publisher> image_publishers_;
  /// By the camera's namespace.
  std::map<std::string, std::shared_ptr<camera_info_manager::CameraInfoManager>> info_managers_;
  std::vector<ros::Subscriber> subscribers_;
  std::vector<ros::ServiceServer> services_;
  std::vector<Output> outputs_;
  std::vector<std::string> topics_;
};

}  // namespace bullet_sim
