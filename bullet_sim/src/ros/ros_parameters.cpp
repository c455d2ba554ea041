#include "ros_parameters.h"

#include <ros/console.h>
#include <ros/param.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace bullet_sim {

namespace {

/// The parameter server's value as YAML, kind for kind.
YAML::Node toYaml(XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return YAML::Node(static_cast<bool>(value));
    case XmlRpc::XmlRpcValue::TypeInt:
      return YAML::Node(static_cast<int>(value));
    case XmlRpc::XmlRpcValue::TypeDouble:
      return YAML::Node(static_cast<double>(value));
    case XmlRpc::XmlRpcValue::TypeString:
      return YAML::Node(static_cast<std::string>(value));
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node list(YAML::NodeType::Sequence);
      for (int i = 0; i < value.size(); ++i) list.push_back(toYaml(value[i]));
      return list;
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node map(YAML::NodeType::Map);
      for (auto& [key, member] : value) map[key] = toYaml(member);
      return map;
    }
    default:  // dates and binary data: no plugin reads them
      return YAML::Node();
  }
}

}  // namespace

ParameterTree RosParameters::fetch(const std::string& ns) const {
  XmlRpc::XmlRpcValue value;
  if (!ros::param::get(ns, value)) return ParameterTree();
  YAML::Emitter out;
  out << toYaml(value);
  return ParameterTree::fromYaml(out.c_str(), "the parameter server's " + ns);
}

namespace {

[[noreturn]] void wrongType(const ros::NodeHandle& node, const std::string& name, const std::string& expected,
                            const XmlRpc::XmlRpcValue& value) {
  throw std::runtime_error("~" + name + " must be " + expected + ", not " + describeParam(value) + " (" +
                           node.resolveName(name) + ")");
}

}  // namespace

std::string describeParam(XmlRpc::XmlRpcValue value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<bool>(value) ? "true" : "false";
    case XmlRpc::XmlRpcValue::TypeString:
      return '"' + static_cast<std::string>(value) + '"';
    default: {
      std::ostringstream text;
      value.write(text);
      return text.str();
    }
  }
}

bool flagParam(const ros::NodeHandle& node, const std::string& name, bool fallback) {
  XmlRpc::XmlRpcValue value;
  if (!node.getParam(name, value)) return fallback;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeBoolean) return static_cast<bool>(value);
  const bool bit = value.getType() == XmlRpc::XmlRpcValue::TypeInt && static_cast<int>(value) >= 0 &&
                   static_cast<int>(value) <= 1;
  if (bit) {
    const bool flag = static_cast<int>(value) == 1;
    ROS_WARN("~%s: %d taken as %s; write true or false", name.c_str(), static_cast<int>(value),
             flag ? "true" : "false");
    return flag;
  }
  wrongType(node, name, "true or false", value);
}

std::optional<double> numberParamIfSet(const ros::NodeHandle& node, const std::string& name) {
  XmlRpc::XmlRpcValue value;
  if (!node.getParam(name, value)) return std::nullopt;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(value);
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(value);
  wrongType(node, name, "a number", value);
}

double numberParam(const ros::NodeHandle& node, const std::string& name, double fallback) {
  return numberParamIfSet(node, name).value_or(fallback);
}

int wholeParam(const ros::NodeHandle& node, const std::string& name, int fallback) {
  XmlRpc::XmlRpcValue value;
  if (!node.getParam(name, value)) return fallback;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(value);
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    const double number = value;
    if (number == std::floor(number) && std::abs(number) <= std::numeric_limits<int>::max())
      return static_cast<int>(number);
  }
  wrongType(node, name, "a whole number", value);
}

std::string textParam(const ros::NodeHandle& node, const std::string& name, const std::string& fallback) {
  XmlRpc::XmlRpcValue value;
  if (!node.getParam(name, value)) return fallback;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeString) return static_cast<std::string>(value);
  wrongType(node, name, "a string", value);
}

}  // namespace bullet_sim
