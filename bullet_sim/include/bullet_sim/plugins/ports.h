// How a plugin talks to the outside: typed, sequenced outputs, typed inputs and typed services, each under a
// name. The ROS node maps each output type to its message, each input type to its subscription and each
// request type to its service, once; a plugin whose types exist needs nothing new in the node.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "bullet_sim/plugins/outputs.h"

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
                 const Stream<Vector3Sample>*, const Stream<ContactsSample>*>;

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

using InputSink = std::variant<InputHandler<Twist>, InputHandler<JointTargets>>;

struct InputPort {
  std::string topic;  ///< relative to the plugin's namespace
  InputSink sink;
};

/// A std_srvs/Empty request: the service does its one thing (hector's calibrate, ...).
struct EmptyRequest {};

/// Serves a request; returns "" when done, else why not (the node then answers with a failure).
template <class Request>
using ServiceHandler = std::function<std::string(const Request& request)>;

using ServiceSink = std::variant<ServiceHandler<EmptyRequest>>;

struct ServicePort {
  std::string name;  ///< relative to the plugin's namespace
  ServiceSink handler;
};

struct PluginPorts {
  std::vector<OutputPort> outputs;
  std::vector<InputPort> inputs;
  std::vector<ServicePort> services;
};

}  // namespace bullet_sim
