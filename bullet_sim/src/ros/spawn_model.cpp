// spawn_model: Gazebo's `rosrun gazebo_ros spawn_model` for bullet_sim. Reads a URDF from a file or a
// parameter and asks the simulator's ~spawn_urdf service to add it; exits non-zero with the reason when that
// fails.
//
//   spawn_model -urdf (-file FILE | -param PARAM) -model NAME [-x X -y Y -z Z -R R -P P -Y Y] [-J joint
//   value]...
//               [-robot_namespace NS] [-gazebo_namespace NS] [-unpause] [-timeout S]
#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <tf2/LinearMath/Quaternion.h>

#include <fstream>
#include <map>
#include <sstream>

#include "bullet_sim/SpawnModel.h"

namespace {

int fail(const std::string& why) {
  std::cerr << "spawn_model: " << why << std::endl;
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "spawn_model", ros::init_options::AnonymousName);
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);

  std::map<std::string, std::string> values;
  bool urdf = false, unpause = false, have_z = false;
  std::vector<std::pair<std::string, std::string>> joints;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& flag = args[i];
    if (flag == "-urdf") {
      urdf = true;
    } else if (flag == "-unpause") {
      unpause = true;
    } else if (flag == "-J" && i + 2 < args.size()) {
      joints.emplace_back(args[i + 1], args[i + 2]);
      i += 2;
    } else if (flag == "-sdf" || flag == "-database" || flag == "-stdin") {
      return fail(flag + " is not supported: bullet_sim spawns URDF (-urdf with -file or -param)");
    } else if (flag.size() > 1 && flag[0] == '-' && i + 1 < args.size()) {
      values[flag.substr(1)] = args[++i];
      have_z |= flag == "-z";
    } else {
      return fail("unexpected argument [" + flag +
                  "]; usage: spawn_model -urdf (-file F | -param P) -model NAME ...");
    }
  }
  if (!urdf) return fail("give -urdf: bullet_sim spawns URDF models");
  if (!values.count("model")) return fail("give -model NAME");

  std::string xml;
  if (values.count("file")) {
    std::ifstream in(values["file"]);
    if (!in) return fail("cannot read -file [" + values["file"] + "]");
    xml.assign(std::istreambuf_iterator<char>(in), {});
  } else if (values.count("param")) {
    if (!ros::param::get(values["param"], xml)) return fail("no parameter [" + values["param"] + "]");
  } else {
    return fail("give -file FILE or -param PARAM");
  }
  if (xml.find_first_not_of(" \t\r\n") == std::string::npos) return fail("the robot description is empty");

  const auto number = [&](const char* key) {
    if (!values.count(key)) return 0.0;
    try {
      return std::stod(values[key]);
    } catch (const std::exception&) {
      throw std::runtime_error(std::string("-") + key + " must be a number, not [" + values[key] + "]");
    }
  };
  bullet_sim::SpawnModel spawn;
  double timeout = 60.0;  // [s] for the simulator's service
  try {
    if (values.count("timeout")) timeout = number("timeout");
    spawn.request.initial_pose.position.x = number("x");
    spawn.request.initial_pose.position.y = number("y");
    spawn.request.initial_pose.position.z = number("z");
    tf2::Quaternion q;
    q.setRPY(number("R"), number("P"), number("Y"));
    spawn.request.initial_pose.orientation.x = q.x();
    spawn.request.initial_pose.orientation.y = q.y();
    spawn.request.initial_pose.orientation.z = q.z();
    spawn.request.initial_pose.orientation.w = q.w();
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  for (const auto& [joint, value] : joints) {
    try {
      spawn.request.joint_positions.push_back(std::stod(value));
    } catch (const std::exception&) {
      return fail("-J " + joint + " must be followed by a number, not [" + value + "]");
    }
    spawn.request.joint_names.push_back(joint);
  }
  spawn.request.model_name = values["model"];
  spawn.request.model_xml = xml;
  spawn.request.robot_namespace = values.count("robot_namespace") ? values["robot_namespace"] : "";
  spawn.request.place_on_ground = !have_z;

  const std::string gazebo = values.count("gazebo_namespace") ? values["gazebo_namespace"] : "/gazebo";
  if (!ros::service::waitForService(gazebo + "/spawn_urdf", ros::Duration(timeout))) {
    return fail("no service " + gazebo + "/spawn_urdf after " + std::to_string(timeout) +
                " s: is the simulator running?");
  }
  if (!ros::service::call(gazebo + "/spawn_urdf", spawn))
    return fail("the call to " + gazebo + "/spawn_urdf failed");
  if (!spawn.response.success) return fail(spawn.response.message);
  ROS_INFO("%s", spawn.response.message.c_str());
  if (unpause) {
    std_srvs::Empty empty;
    if (!ros::service::call(gazebo + "/unpause_physics", empty))
      return fail("could not unpause the simulation");
  }
  return 0;
}
