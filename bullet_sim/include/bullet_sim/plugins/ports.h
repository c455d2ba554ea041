// How a plugin talks to the outside: typed, sequenced outputs, typed inputs, typed services and typed
// actions, each under a name. The ROS node maps each output type to its message, each input type to its
// subscription, each request type to its service and each action type to its action server, once; a plugin
// whose types exist needs nothing new in the node.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "bullet_sim/plugins/actions.h"
#include "bullet_sim/plugins/input_checks.h"
#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/requests.h"

namespace bullet_sim {

/// A plugin's stream of samples of one type: the latest, and how many there were (a new one when the count
/// changes).
template <class Sample>
class Stream {
 public:
  const Sample& latest() const { return latest_; }
  uint64_t count() const { return count_; }
  /// The sample to fill; it keeps the previous one's contents (frames, sizes) until overwritten.
  Sample& next() { return latest_; }
  /// Makes the filled sample the latest.
  void publish() { ++count_; }

 private:
  Sample latest_{};
  uint64_t count_ = 0;
};

using OutputStream =
    std::variant<const Stream<Odometry>*, const Stream<TransformSample>*, const Stream<JointStateSample>*,
                 const Stream<LaserScan>*, const Stream<PointCloud>*, const Stream<LegacyPointCloud>*,
                 const Stream<ImuSample>*, const Stream<CameraImage>*, const Stream<CameraInfo>*,
                 const Stream<ColouredCloud>*, const Stream<RangeSample>*, const Stream<NavSatFixSample>*,
                 const Stream<Vector3Sample>*, const Stream<ContactsSample>*,
                 const Stream<JointControllerState>*, const Stream<StampedTwist>*,
                 const Stream<JointTrajectoryControllerState>*>;

/// Whether anyone listens to an output. The node sets it from the topic's subscribers before each step; a
/// plugin skips work (a camera's rendering) that nobody wants. Without a node, everything is wanted.
struct Demand {
  bool wanted = true;
};

struct OutputPort {
  std::string topic;  ///< relative to the plugin's namespace; "" for transforms, which go to /tf
  OutputStream stream;
  Demand* demand = nullptr;  ///< the plugin's, for outputs it computes only on demand
};

/// Takes an input at `sim_time` [s]; returns "" when taken, else why it was refused (the node warns).
template <class Input>
using InputHandler = std::function<std::string(const Input& input, double sim_time)>;

/// `handler` behind checkInput: a message that fails it is dropped, with the reason, before the plugin sees
/// it.
template <class Input>
InputHandler<Input> checkedInput(InputHandler<Input> handler) {
  return [handler = std::move(handler)](const Input& input, double sim_time) -> std::string {
    try {
      checkInput(input);
    } catch (const std::invalid_argument& e) {
      return std::string("a message whose ") + e.what();
    }
    return handler(input, sim_time);
  };
}

using InputSink =
    std::variant<InputHandler<Twist>, InputHandler<JointTrajectory>, InputHandler<Float64Command>,
                 InputHandler<Float64ArrayCommand>, InputHandler<BoolCommand>>;

/// How many publish to an input. The node sets it from the subscription as each message comes in, before the
/// input's handler runs (diff_drive_controller refuses commands from several publishers when asked to);
/// without a node, one.
struct Publishers {
  uint32_t count = 1;
};

struct InputPort {
  std::string topic;  ///< relative to the plugin's namespace
  InputSink sink;
  Publishers* publishers = nullptr;  ///< the plugin's, for inputs that care how many publish to them
};

/// Serves a request and fills its reply; returns "" when done, else why not (the node then answers with a
/// failure).
template <class Request>
using ServiceHandler = std::function<std::string(const Request& request, typename Request::Reply& reply)>;

/// A ServiceHandler from a callable of (request, reply), or of (request) alone for a request with nothing to
/// reply.
template <class Request, class Handler>
ServiceHandler<Request> serviceHandler(Handler handler) {
  if constexpr (std::is_invocable_v<Handler&, const Request&>) {
    return [handler](const Request& request, typename Request::Reply&) { return handler(request); };
  } else {
    return handler;
  }
}

using ServiceSink =
    std::variant<ServiceHandler<EmptyRequest>, ServiceHandler<LoadControllerRequest>,
                 ServiceHandler<UnloadControllerRequest>, ServiceHandler<SwitchControllerRequest>,
                 ServiceHandler<ListControllersRequest>, ServiceHandler<ListControllerTypesRequest>,
                 ServiceHandler<ReloadControllerLibrariesRequest>,
                 ServiceHandler<QueryTrajectoryStateRequest>>;

struct ServicePort {
  std::string name;  ///< relative to the plugin's namespace
  ServiceSink handler;
};

/// An action's goals as a plugin serves them (actionlib's ActionServer without ROS): the node hands it each
/// goal and each cancel request, at `sim_time` [s], and sends what it reports.
template <class Action>
struct ActionHandlers {
  /// Accepts or rejects a goal at once.
  std::function<GoalDecision<Action>(GoalId goal, const typename Action::Goal& request, double sim_time)>
      goal;
  /// A client asks to cancel `goal`; the plugin reports the goal's end if it ends it.
  std::function<void(GoalId goal, double sim_time)> cancel;
  /// Shared, so that what a controller reported before its unload still reaches the node.
  std::shared_ptr<GoalReports<Action>> reports;
};

using ActionSink = std::variant<ActionHandlers<FollowJointTrajectoryAction>>;

struct ActionPort {
  std::string name;  ///< relative to the plugin's namespace
  ActionSink sink;
};

struct PluginPorts {
  std::vector<OutputPort> outputs;
  std::vector<InputPort> inputs;
  std::vector<ServicePort> services;
  std::vector<ActionPort> actions;

  template <class Sample>
  void addOutput(const std::string& topic, const Stream<Sample>& stream, Demand* demand = nullptr) {
    outputs.push_back({topic, &stream, demand});
  }
  template <class Input>
  void addInput(const std::string& topic, InputHandler<Input> handler, Publishers* publishers = nullptr) {
    inputs.push_back({topic, checkedInput(std::move(handler)), publishers});
  }
  template <class Request, class Handler>
  void addService(const std::string& name, Handler handler) {
    services.push_back({name, serviceHandler<Request>(std::move(handler))});
  }
  template <class Action>
  void addAction(const std::string& name, ActionHandlers<Action> handlers) {
    // A goal that fails checkInput is rejected as invalid before the plugin sees it.
    handlers.goal = [goal = std::move(handlers.goal)](GoalId id, const typename Action::Goal& request,
                                                      double sim_time) {
      try {
        checkInput(request);
      } catch (const std::invalid_argument& e) {
        GoalDecision<Action> rejected;
        rejected.result.error_code = Action::Result::kInvalidGoal;
        rejected.result.error_string = std::string("a goal whose ") + e.what();
        return rejected;
      }
      return goal(id, request, sim_time);
    };
    actions.push_back({name, std::move(handlers)});
  }
};

/// Ports that appear while a plugin runs and go again: a ros_control controller's, from its load to its
/// unload. The node connects a group when it appears and drops it when it goes.
struct PortGroup {
  uint64_t id = 0;    ///< never reused within a plugin
  std::string name;   ///< for the log, e.g. "controller [husky_velocity_controller]"
  const PluginPorts* ports = nullptr;
};

}  // namespace bullet_sim
