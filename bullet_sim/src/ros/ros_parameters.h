// The parameter server as the core's ParameterSource: what plugins read at run time (ros_control's
// controllers and pid_gains) comes from here, as a ParameterTree. And a node's own parameters, by type.
#pragma once

#include <ros/node_handle.h>

#include <optional>
#include <string>

#include "bullet_sim/plugins/parameter_tree.h"

namespace bullet_sim {

class RosParameters : public ParameterSource {
 public:
  /// The parameters under `ns` as they are now; an empty tree when there are none.
  ParameterTree fetch(const std::string& ns) const override;
};

/// A node's own parameter `name` under `node` (its private handle: ~name), or `fallback` when it is not set.
/// roscpp's param() takes the fallback, silently, for a value of another type; these throw a
/// std::runtime_error that names the parameter and the value. As roscpp, a number takes an integer and an
/// integer a whole number written as a double (2.0); a flag takes 0 and 1 too, with a warning.
bool flagParam(const ros::NodeHandle& node, const std::string& name, bool fallback);
double numberParam(const ros::NodeHandle& node, const std::string& name, double fallback);
/// As numberParam, without a fallback: nothing when the parameter is not set.
std::optional<double> numberParamIfSet(const ros::NodeHandle& node, const std::string& name);
int wholeParam(const ros::NodeHandle& node, const std::string& name, int fallback);
std::string textParam(const ros::NodeHandle& node, const std::string& name, const std::string& fallback);
/// A parameter's value as a user wrote it: "two" with its quotes, true, 1.5, [1, 2].
std::string describeParam(XmlRpc::XmlRpcValue value);

}  // namespace bullet_sim
