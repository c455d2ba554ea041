// The ROS face of one spawned robot: for every plugin, a subscription per input, a publisher per output, a
// server per service and an action server per action, in the robot's namespace and with its frame prefix.
// Each output type maps to its message, each input type to its subscription, each request type to its service
// and each action type to its action server, in one place. Ports that appear while the robot runs (a
// ros_control controller's, from its load to its unload) are connected when they appear and dropped when they
// go. Runs between steps, on the node's thread.
#pragma once

#include <image_transport/publisher.h>
#include <ros/ros.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "bullet_sim/simulation/simulation.h"
#include "listened_publisher.h"
#include "messages.h"

namespace camera_info_manager {
class CameraInfoManager;
}

namespace bullet_sim {

class ActionConnection;

/// Which robot publishes which child frame on /tf, for the one warning when two publish the same.
struct FrameOwners {
  std::map<std::string, std::string> robot_of;  ///< child frame -> robot
  std::set<std::string> warned;                 ///< "frame robot" pairs warned about
};

class RobotAdapter {
 public:
  /// `robot_namespace` from the spawn request overrides every plugin's <robotNamespace> when it is not empty.
  /// Each plugin's frames take the tf_prefix parameter by its type's rule (TfPrefixRule), never the namespace
  /// by itself. `owners` is shared by the robots of one simulator; `sim_time` tells when an input arrived.
  RobotAdapter(Robot& robot, const std::string& robot_namespace, const ListenedPublisher& tf,
               FrameOwners& owners, std::function<double()> sim_time);
  ~RobotAdapter();

  /// Publishes what the plugins produced since the last call, and tells each plugin whether its on-demand
  /// outputs (camera images) have subscribers now and how many publish to its inputs.
  void publish();
  /// Connects the port groups that appeared since the last call and drops those that went.
  void refreshPorts();

  /// The resolved name of one of `plugin`'s topics (relative to its namespace).
  std::string topicName(const Plugin& plugin, const std::string& topic) const {
    return handleFor(plugin.robotNamespace()).resolveName(topic);
  }
  /// The topics this robot advertises and subscribes, for the log.
  const std::vector<std::string>& topics() const { return topics_; }
  /// What its plugins could not connect (a topic of another type, a name ROS refuses): each plugin runs
  /// without it, as in Gazebo; the spawn's answer says it.
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  struct Output {
    std::function<uint64_t()> count;  ///< changes when the plugin has a new sample
    std::function<void()> publish;
    uint64_t seen = 0;
    Demand* demand = nullptr;  ///< the plugin's, set from the subscriber count
    std::function<uint32_t()> subscribers;
  };
  /// What one set of ports is connected to: dropped together when its port group goes.
  struct Connections {
    std::vector<ros::Publisher> publishers;
    std::vector<image_transport::Publisher> image_publishers;
    std::vector<ros::Subscriber> subscribers;
    std::vector<ros::ServiceServer> services;
    std::vector<std::shared_ptr<ActionConnection>> actions;
    std::vector<Output> outputs;
  };
  /// A plugin whose port groups come and go, and the revision of them connected.
  struct Watched {
    const Plugin* plugin;
    uint64_t revision;
  };
  struct Connection;  ///< what connect() needs of one plugin

  void connect(const Plugin& plugin, const PluginPorts& ports, Connections& into);
  void reconnectGroups(const Plugin& plugin);
  void publish(Connections& connections);
  void advertise(const Connection& plugin, const OutputPort& port);
  void subscribe(const Connection& plugin, const InputPort& port);
  template <class Message, class Input>
  void subscribeAs(const Connection& plugin, const InputPort& port, const InputHandler<Input>& handler);
  void serve(const Connection& plugin, const ServicePort& port);
  void serveAction(const Connection& plugin, const ActionPort& port);
  template <class Message, class Sample, class Convert>
  void advertiseStream(const Connection& plugin, const OutputPort& port, const Stream<Sample>* stream,
                       Convert convert);
  /// Images go through image_transport (raw only: Debian has no compressed transport).
  void advertiseImages(const Connection& plugin, const OutputPort& port, const Stream<CameraImage>* stream);
  /// camera_info comes from the camera's camera_info_manager, which serves set_camera_info.
  void advertiseCameraInfo(const Connection& plugin, const OutputPort& port,
                           const Stream<CameraInfo>* stream);
  void broadcast(const Connection& plugin, const Stream<TransformSample>* stream);
  ros::NodeHandle handleFor(const std::string& plugin_namespace) const;
  /// The tf_prefix of `plugin`'s frames, read from the parameter server by its rule.
  FramePrefix framesOf(const Plugin& plugin) const;
  /// Warns once when another robot already publishes `child` on /tf.
  void claimFrame(const std::string& child);
  /// Warns and keeps `why` for problems().
  void cannotConnect(const std::string& why);
  /// Warns, as cannotConnect, when another node publishes `topic` as a type other than `type`: roscpp
  /// connects the two only when their types agree, so the plugin would hear or reach nobody there.
  void checkTypeElsewhere(const Connection& plugin, const std::string& what, const std::string& type,
                          const std::string& topic);

  const std::string robot_name_;
  std::string namespace_;
  const ListenedPublisher& tf_;  ///< /tf, shared by the robots
  FrameOwners& owners_;
  std::function<double()> sim_time_;
  /// By the camera's namespace.
  std::map<std::string, std::shared_ptr<camera_info_manager::CameraInfoManager>> info_managers_;
  Connections fixed_;  ///< the plugins' own ports, for the robot's life
  std::vector<Watched> watched_;
  std::map<std::pair<const Plugin*, uint64_t>, Connections> groups_;  ///< by plugin and port group id
  std::vector<std::string> topics_;
  std::vector<std::string> problems_;
  std::optional<std::map<std::string, std::string>> published_types_;  ///< the master's, asked once
};

}  // namespace bullet_sim
