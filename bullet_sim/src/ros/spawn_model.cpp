// spawn_model: Gazebo's `rosrun gazebo_ros spawn_model` for bullet_sim. Reads a URDF from a file or a
// parameter and asks the simulator's ~spawn_urdf service to add it; exits non-zero with the reason when that
// fails.
//
//   spawn_model -urdf (-file FILE | -param PARAM) -model NAME [-x X -y Y -z Z -R R -P P -Y Y] [-J joint
//   value]...
//               [-robot_namespace NS] [-gazebo_namespace NS] [-unpause] [-wait MODEL] [-timeout S]
#include <gazebo_msgs/GetWorldProperties.h>
#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <tf2/LinearMath/Quaternion.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bullet_sim/SpawnModel.h"
#include "bullet_sim/common/files.h"
#include "bullet_sim/common/limits.h"

namespace {

/// A reason to stop, for stderr and a non-zero exit.
struct Refusal : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Arguments {
  std::map<std::string, std::string> values;  ///< -name value, without the dash
  bool urdf = false, unpause = false, have_z = false;
  std::vector<std::pair<std::string, std::string>> joints;  ///< -J joint value
};

/// Gazebo's spawn_model's flags that take a value, and ours (-timeout).
const std::set<std::string> kValueFlags = {"-file", "-param", "-model", "-reference_frame",
                                           "-gazebo_namespace", "-robot_namespace", "-wait", "-x", "-y", "-z",
                                           "-R", "-P", "-Y", "-timeout"};

Arguments parseFlags(const std::vector<std::string>& args) {
  Arguments parsed;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& flag = args[i];
    if (flag == "-urdf") {
      parsed.urdf = true;
    } else if (flag == "-unpause") {
      parsed.unpause = true;
    } else if (flag == "-J" && i + 2 < args.size()) {
      parsed.joints.emplace_back(args[i + 1], args[i + 2]);
      i += 2;
    } else if (flag == "-package_to_model" || flag == "-b") {
      ROS_WARN("spawn_model: %s is accepted and not honoured here", flag.c_str());
    } else if (flag == "-sdf" || flag == "-database" || flag == "-stdin") {
      throw Refusal(flag +
                    " is not supported here: this spawn_model takes -urdf with -file or -param; spawn " +
                    "SDF with gazebo_ros's spawn_model or the simulator's spawn_sdf_model service");
    } else if (kValueFlags.count(flag) && i + 1 < args.size()) {
      parsed.values[flag.substr(1)] = args[++i];
      parsed.have_z |= flag == "-z";
    } else {
      throw Refusal("unexpected argument [" + flag +
                    "]; usage: spawn_model -urdf (-file F | -param P) -model NAME ...");
    }
  }
  const auto frame = parsed.values.find("reference_frame");
  if (frame != parsed.values.end() && !frame->second.empty() && frame->second != "world")
    ROS_WARN("spawn_model: -reference_frame %s is not honoured: the pose is in the world",
             frame->second.c_str());
  if (!parsed.urdf) throw Refusal("give -urdf: bullet_sim spawns URDF models");
  if (!parsed.values.count("model")) throw Refusal("give -model NAME");
  return parsed;
}

/// The text of a -file: a regular file (not a directory, a FIFO or a device) of at most the simulator's
/// default max_description_bytes.
std::string readFile(const std::string& path) {
  const size_t max_bytes = bullet_sim::Limits().max_description_bytes;
  if (auto problem = bullet_sim::fileProblem(path, max_bytes, "max_description_bytes"))
    throw Refusal("-file [" + path + "] " + *problem);
  try {
    return bullet_sim::readRegularFile(path, max_bytes, "max_description_bytes");
  } catch (const std::runtime_error& e) {
    throw Refusal(std::string("-file ") + e.what());
  }
}

std::string readDescription(const Arguments& arguments) {
  std::string xml;
  if (arguments.values.count("file")) {
    xml = readFile(arguments.values.at("file"));
  } else if (arguments.values.count("param")) {
    const std::string& param = arguments.values.at("param");
    if (!ros::param::get(param, xml)) throw Refusal("no parameter [" + param + "]");
  } else {
    throw Refusal("give -file FILE or -param PARAM");
  }
  if (xml.find_first_not_of(" \t\r\n") == std::string::npos) throw Refusal("the robot description is empty");
  return xml;
}

double number(const Arguments& arguments, const std::string& key, double fallback = 0) {
  const auto found = arguments.values.find(key);
  if (found == arguments.values.end()) return fallback;
  try {
    return std::stod(found->second);
  } catch (const std::exception&) {
    throw Refusal("-" + key + " must be a number, not [" + found->second + "]");
  }
}

bullet_sim::SpawnModel::Request makeRequest(const Arguments& arguments, const std::string& xml) {
  bullet_sim::SpawnModel::Request request;
  request.initial_pose.position.x = number(arguments, "x");
  request.initial_pose.position.y = number(arguments, "y");
  request.initial_pose.position.z = number(arguments, "z");
  tf2::Quaternion q;
  q.setRPY(number(arguments, "R"), number(arguments, "P"), number(arguments, "Y"));
  request.initial_pose.orientation.x = q.x();
  request.initial_pose.orientation.y = q.y();
  request.initial_pose.orientation.z = q.z();
  request.initial_pose.orientation.w = q.w();
  for (const auto& [joint, value] : arguments.joints) {
    try {
      request.joint_positions.push_back(std::stod(value));
    } catch (const std::exception&) {
      throw Refusal("-J " + joint + " must be followed by a number, not [" + value + "]");
    }
    request.joint_names.push_back(joint);
  }
  request.model_name = arguments.values.at("model");
  request.model_xml = xml;
  const auto ns = arguments.values.find("robot_namespace");
  request.robot_namespace = ns == arguments.values.end() ? "" : ns->second;
  request.place_on_ground = !arguments.have_z;
  return request;
}

std::string seconds(double value) {
  std::ostringstream text;
  text << value << " s";
  return text.str();
}

/// -wait MODEL: until the world holds MODEL, asked of the simulator every 20 ms of wall time (Gazebo's
/// spawn_model reads model_states at 10 Hz of sim time, which a paused world never reaches).
void waitForModel(const std::string& gazebo, const std::string& model, double timeout) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  const std::string service = gazebo + "/get_world_properties";
  // One connection for all the asking (made again if it drops): a fleet's spawners would otherwise each ask
  // the master where the service is, fifty times a second.
  ros::NodeHandle node;
  ros::ServiceClient world;
  ROS_INFO("Waiting for model %s before proceeding.", model.c_str());
  while (ros::ok() && ros::WallTime::now() < deadline) {
    if (!world.isValid()) world = node.serviceClient<gazebo_msgs::GetWorldProperties>(service, true);
    gazebo_msgs::GetWorldProperties properties;
    if (world.call(properties)) {
      const auto& names = properties.response.model_names;
      if (std::find(names.begin(), names.end(), model) != names.end()) return;
    }
    ros::WallDuration(0.02).sleep();  // the period of asking, within the deadline
  }
  if (!ros::ok()) throw Refusal("-wait " + model + ": stopped before that model was in the world");
  throw Refusal("-wait " + model + ": no model of that name in the world after " + seconds(timeout) +
                " (-timeout)");
}

/// Asks the simulator's spawn service, and unpauses it when asked to.
void spawn(const Arguments& arguments, bullet_sim::SpawnModel& call) {
  const double timeout = number(arguments, "timeout", 60.0);  // [s] for the simulator's service, and -wait
  const auto ns = arguments.values.find("gazebo_namespace");
  const std::string gazebo = ns == arguments.values.end() ? "/gazebo" : ns->second;
  if (!ros::service::waitForService(gazebo + "/spawn_urdf", ros::Duration(timeout))) {
    throw Refusal("no service " + gazebo + "/spawn_urdf after " + seconds(timeout) +
                  ": is the simulator running?");
  }
  const auto wait = arguments.values.find("wait");
  if (wait != arguments.values.end()) waitForModel(gazebo, wait->second, timeout);
  if (!ros::service::call(gazebo + "/spawn_urdf", call))
    throw Refusal("the call to " + gazebo + "/spawn_urdf failed");
  if (!call.response.success) throw Refusal(call.response.message);
  ROS_INFO("%s", call.response.message.c_str());
  std_srvs::Empty empty;
  if (arguments.unpause && !ros::service::call(gazebo + "/unpause_physics", empty))
    throw Refusal("could not unpause the simulation");
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "spawn_model", ros::init_options::AnonymousName);
  const ros::NodeHandle node;  // starts the node: ros::ok() holds until it is stopped
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  try {
    const Arguments arguments = parseFlags(args);
    bullet_sim::SpawnModel call;
    call.request = makeRequest(arguments, readDescription(arguments));
    spawn(arguments, call);
  } catch (const Refusal& refusal) {
    std::cerr << "spawn_model: " << refusal.what() << std::endl;
    return 1;
  }
  return 0;
}
