// The live viewer in the simulator node (bullet_sim/web_viewer.h): started by ~web_port, fed after every
// step, and its pages' commands queued into the node's callback queue, where service calls wait, so that they
// run between steps. Teleop publishes a geometry_msgs/Twist on the chosen robot's velocity topic (its
// cmd_vel).
//
// Params: ~web_port [0 = off], ~web_address [127.0.0.1], ~web_allowed_origins [none besides its own: a list,
// or one string of origins separated by spaces or commas], ~web_control [false: pages from beyond this
// machine may only watch].
#pragma once

#include <ros/ros.h>

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "bullet_sim/web/web_viewer.h"

namespace bullet_sim {

class NodeWebView {
 public:
  /// What the node does for a page.
  struct Actions {
    std::function<void()> pause;
    std::function<void()> resume;
    std::function<void()> reset;
    /// The resolved name of a robot's velocity input ("/cmd_vel"), or "" when it has none.
    std::function<std::string(const std::string& robot)> velocity_topic;
  };

  /// The viewer ~web_port asks for, or nullptr when it is 0. When it cannot serve (the port is taken,
  /// three.js is missing), logs one error saying why and returns nullptr: the simulation runs on without it.
  /// Throws std::runtime_error for a parameter that is not valid.
  static std::unique_ptr<NodeWebView> fromParameters(const ros::NodeHandle& private_node, Actions actions);
  ~NodeWebView();

  /// After every step, and while paused.
  void update(const Simulation& simulation, bool paused) { viewer_->update(simulation, paused); }
  void modelsChanged() { viewer_->modelsChanged(); }

 private:
  explicit NodeWebView(Actions actions) : actions_(std::move(actions)) {}
  /// On the node's thread, between steps.
  void apply(const ViewerCommand& command);
  void teleop(const ViewerCommand& command);

  Actions actions_;
  std::map<std::string, ros::Publisher> velocity_publishers_;  ///< by topic
  std::unique_ptr<WebViewer> viewer_;                          ///< stopped first: its thread queues commands
};

}  // namespace bullet_sim
