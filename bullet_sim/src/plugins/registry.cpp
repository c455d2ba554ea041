#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "bullet_sim/plugins/ackermann_drive.h"
#include "bullet_sim/plugins/bumper.h"
#include "bullet_sim/plugins/drive_support.h"
#include "bullet_sim/plugins/force_based_move.h"
#include "bullet_sim/plugins/ground_truth.h"
#include "bullet_sim/plugins/hector_gps.h"
#include "bullet_sim/plugins/hector_imu.h"
#include "bullet_sim/plugins/imu.h"
#include "bullet_sim/plugins/joint_position.h"
#include "bullet_sim/plugins/joint_states.h"
#include "bullet_sim/plugins/pinhole_camera.h"
#include "bullet_sim/plugins/planar_move.h"
#include "bullet_sim/plugins/range_sensor.h"
#include "bullet_sim/plugins/ray_lidar.h"
#include "bullet_sim/plugins/ros_control/diff_drive_controller.h"
#include "bullet_sim/plugins/ros_control/joint_command_controllers.h"
#include "bullet_sim/plugins/ros_control/joint_state_controller.h"
#include "bullet_sim/plugins/ros_control/joint_trajectory_controller.h"
#include "bullet_sim/plugins/ros_control/pid_joint_controllers.h"
#include "bullet_sim/plugins/ros_control/ros_control_plugin.h"
#include "bullet_sim/plugins/wheeled_drive.h"

namespace bullet_sim {

namespace {

const std::vector<std::string> kRaySensors = {"ray", "gpu_ray"};
const std::vector<std::string> kCameraSensors = {"camera", "wideanglecamera"};

PluginRegistry makeBuiltin() {
  PluginRegistry registry;
  for (PluginType type : {
           pluginType<WheeledDrive>("libgazebo_ros_diff_drive.so", {}, parseDiffDrive),
           pluginType<WheeledDrive>("libgazebo_ros_skid_steer_drive.so", {}, parseSkidSteer),
           pluginType<AckermannDrive>("libgazebo_ros_ackermann_drive.so", {}, parseAckermann),  // ROS 2's
           pluginType<JointStates>("libgazebo_ros_joint_state_publisher.so", {}, parseJointStates),
           pluginType<JointPosition>("libgazebo_ros_joint_pose_trajectory.so", {}, parseJointPosition),
           pluginType<GroundTruth>("libgazebo_ros_p3d.so", {}, parseGroundTruth),
           pluginType<Imu>("libgazebo_ros_imu.so", {}, parseImuPlugin),
           pluginType<Imu>("libgazebo_ros_imu_sensor.so", {"imu"}, parseImuSensor),
           pluginType<RayLidar>("libgazebo_ros_laser.so", kRaySensors, parseRayLidar),
           pluginType<RayLidar>("libgazebo_ros_gpu_laser.so", kRaySensors, parseRayLidar),
           pluginType<RayLidar>("libgazebo_ros_velodyne_laser.so", kRaySensors, parseRayLidar),
           pluginType<RayLidar>("libgazebo_ros_velodyne_gpu_laser.so", kRaySensors, parseRayLidar),
           pluginType<RayLidar>("libgazebo_ros_block_laser.so", kRaySensors, parseRayLidar),
           pluginType<PinholeCamera>("libgazebo_ros_camera.so", kCameraSensors, parseCamera),
           pluginType<PinholeCamera>("libgazebo_ros_openni_kinect.so", {"depth"}, parseDepthCamera),
           pluginType<PinholeCamera>("libgazebo_ros_depth_camera.so", {"depth"}, parseDepthCamera),
           pluginType<RangeSensor>("libgazebo_ros_range.so", {"ray"}, parseRange),
           pluginType<HectorImu>("libhector_gazebo_ros_imu.so", {}, parseHectorImu),
           pluginType<HectorGps>("libhector_gazebo_ros_gps.so", {}, parseHectorGps),
           pluginType<Bumper>("libgazebo_ros_bumper.so", {"contact"}, parseBumper),
           pluginType<PlanarMove>("libgazebo_ros_planar_move.so", {}, parsePlanarMove),
           // hector_gazebo_plugins' force-based move:
           pluginType<ForceBasedMove>("libgazebo_ros_force_based_move.so", {}, parseForceBasedMove),
           pluginType<RosControl>("libgazebo_ros_control.so", {}, parseRosControl),
       }) {
    registry.add(std::move(type));
  }
  return registry;
}

ControllerRegistry makeBuiltinControllers() {
  using Joints = JointGroupCommandController;
  using Pid = PidJointController;
  using Trajectory = JointTrajectoryController;
  constexpr auto kEffort = JointInterface::kEffort, kVelocity = JointInterface::kVelocity,
                 kPosition = JointInterface::kPosition;
  ControllerRegistry registry;
  for (ControllerType type : {
           controllerType<JointStateController>("joint_state_controller/JointStateController"),
           controllerType<DiffDriveController>("diff_drive_controller/DiffDriveController"),
           controllerType<Joints>("velocity_controllers/JointVelocityController", kVelocity, true),
           controllerType<Joints>("position_controllers/JointPositionController", kPosition, true),
           controllerType<Joints>("effort_controllers/JointEffortController", kEffort, true),
           controllerType<Pid>("effort_controllers/JointPositionController", Pid::Target::kPosition),
           controllerType<Pid>("effort_controllers/JointVelocityController", Pid::Target::kVelocity),
           controllerType<Joints>("velocity_controllers/JointGroupVelocityController", kVelocity, false),
           controllerType<Joints>("position_controllers/JointGroupPositionController", kPosition, false),
           controllerType<Joints>("effort_controllers/JointGroupEffortController", kEffort, false),
           controllerType<Trajectory>("position_controllers/JointTrajectoryController", kPosition),
           controllerType<Trajectory>("velocity_controllers/JointTrajectoryController", kVelocity),
           controllerType<Trajectory>("effort_controllers/JointTrajectoryController", kEffort),
       }) {
    registry.add(std::move(type));
  }
  return registry;
}

}  // namespace

const PluginRegistry& PluginRegistry::builtin() {
  static const PluginRegistry registry = makeBuiltin();
  return registry;
}

void PluginRegistry::add(PluginType type) {
  auto same = std::find_if(types_.begin(), types_.end(), [&](const PluginType& known) {
    return known.filename == type.filename && known.sensor_types == type.sensor_types;
  });
  if (same != types_.end()) {
    *same = std::move(type);
  } else {
    types_.push_back(std::move(type));
  }
}

const PluginType* PluginRegistry::find(const std::string& filename, const std::string* sensor_type) const {
  for (const auto& type : types_) {
    if (type.filename != filename) continue;
    const bool serves = sensor_type
                            ? std::count(type.sensor_types.begin(), type.sensor_types.end(), *sensor_type) > 0
                            : type.sensor_types.empty();
    if (serves) return &type;
  }
  return nullptr;
}

std::shared_ptr<const PluginConfig> PluginRegistry::parse(const DeclarationSource& source) const {
  const PluginDeclaration& declaration = source.declaration;
  const auto& sensor = declaration.sensor;
  if (const PluginType* type = find(declaration.filename, sensor ? &sensor->type : nullptr)) {
    auto config = type->parse(source);
    source.tags.finish();  // one warning for each tag the parser did not read
    return config;
  }
  if (sensor) {
    source.diagnostics.warning(declaration.where() + " of type [" + sensor->type + "] with plugin [" +
                               declaration.filename + "] is not simulated by bullet_sim: ignored");
  } else {
    source.diagnostics.warning(declaration.where() + " filename [" + declaration.filename +
                               "] is not a plugin bullet_sim simulates: ignored");
  }
  return nullptr;
}

void PluginRegistry::checkModel(const ModelSpec& model, Diagnostics& diagnostics) const {
  std::vector<const PluginDeclaration*> drives;
  for (const auto& plugin : model.plugins) {
    if (plugin.configAs<DriveConfigHead>()) drives.push_back(&plugin);
  }
  if (drives.size() > 1) {
    std::string names;
    for (const auto* drive : drives) names += (names.empty() ? "" : " and ") + drive->where();
    diagnostics.error("the robot has " + std::to_string(drives.size()) + " drives, " + names +
                      ": they would fight over its wheels and both publish its odometry; keep one");
  }
}

void capUpdateRate(PluginConfig& config, const DeclarationSource& source) {
  const double limit = source.limits.max_rate;
  if (config.update_rate <= limit) return;
  std::ostringstream message;
  message << source.declaration.where() << ": update rate " << config.update_rate
          << " Hz is above the limit of " << limit << " Hz (max_rate): " << limit
          << " Hz is used (no plugin updates more often than once a step)";
  source.diagnostics.warning(message.str());
  config.update_rate = limit;
}

std::unique_ptr<Plugin> PluginRegistry::create(const PluginDeclaration& declaration,
                                               const PluginSetup& setup) const {
  const auto& sensor = declaration.sensor;
  const PluginType* type = find(declaration.filename, sensor ? &sensor->type : nullptr);
  if (!type) {
    throw std::invalid_argument(declaration.where() + " filename [" + declaration.filename +
                                "] was parsed by another plugin registry than the simulation's");
  }
  return type->create(declaration, setup);
}

const ControllerRegistry& ControllerRegistry::builtin() {
  static const ControllerRegistry registry = makeBuiltinControllers();
  return registry;
}

void ControllerRegistry::add(ControllerType type) {
  auto same = std::find_if(types_.begin(), types_.end(),
                           [&](const ControllerType& known) { return known.name == type.name; });
  if (same != types_.end()) {
    *same = std::move(type);
  } else {
    types_.push_back(std::move(type));
  }
}

const ControllerType* ControllerRegistry::find(const std::string& name) const {
  for (const auto& type : types_) {
    if (type.name == name) return &type;
  }
  return nullptr;
}

std::vector<std::string> ControllerRegistry::names() const {
  std::vector<std::string> names;
  for (const auto& type : types_) names.push_back(type.name);
  return names;
}

ModelSpec parseModel(const std::string& urdf_xml, const std::string& source, const PackageResolver& resolver,
                     std::vector<std::string>* warnings, const Limits& limits) {
  return parseModel(urdf_xml, source, resolver, PluginRegistry::builtin(), warnings, limits);
}

}  // namespace bullet_sim
