#include "ros_parameters.h"

#include <ros/param.h>
#include <yaml-cpp/yaml.h>

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

}  // namespace bullet_sim
