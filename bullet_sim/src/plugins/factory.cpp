#include "bullet_sim/plugins/factory.h"

#include "bullet_sim/plugins/ackermann_drive.h"
#include "bullet_sim/plugins/ground_truth.h"
#include "bullet_sim/plugins/imu.h"
#include "bullet_sim/plugins/joint_position.h"
#include "bullet_sim/plugins/joint_states.h"
#include "bullet_sim/plugins/ray_lidar.h"
#include "bullet_sim/plugins/wheeled_drive.h"

namespace bullet_sim {

namespace {

const std::set<std::string> kLaserPlugins = {
    "libgazebo_ros_laser.so", "libgazebo_ros_gpu_laser.so", "libgazebo_ros_velodyne_laser.so",
    "libgazebo_ros_velodyne_gpu_laser.so", "libgazebo_ros_block_laser.so"};

}  // namespace

std::vector<std::unique_ptr<Plugin>> createPlugins(const ModelSpec& model, const RobotBody& body,
                                                   const PluginContext& context, Diagnostics& diagnostics) {
  std::vector<std::unique_ptr<Plugin>> plugins;
  const auto seed = [&](const std::string& name) {
    return context.seed ^ stableHash(context.robot_name + "/" + name);
  };

  for (const auto& spec : model.plugins) {
    const std::string where = "plugin [" + spec.name + "]";
    if (spec.filename == "libgazebo_ros_diff_drive.so" ||
        spec.filename == "libgazebo_ros_skid_steer_drive.so") {
      PluginTags tags(spec.element, where, diagnostics);
      DriveConfig config = spec.filename == "libgazebo_ros_diff_drive.so" ? parseDiffDriveConfig(tags)
                                                                          : parseSkidSteerConfig(tags);
      tags.finish();
      plugins.push_back(
          std::make_unique<WheeledDrive>(spec.name, std::move(config), model, body, diagnostics));
    } else if (spec.filename == "libgazebo_ros_ackermann_drive.so") {  // ROS 2's tags: our extension
      PluginTags tags(spec.element, where, diagnostics);
      AckermannConfig config = parseAckermannConfig(tags);
      tags.finish();
      plugins.push_back(
          std::make_unique<AckermannDrive>(spec.name, std::move(config), model, body, diagnostics));
    } else if (spec.filename == "libgazebo_ros_joint_state_publisher.so") {
      plugins.push_back(std::make_unique<JointStates>(spec, model, body, diagnostics));
    } else if (spec.filename == "libgazebo_ros_joint_pose_trajectory.so") {
      plugins.push_back(std::make_unique<JointPosition>(spec, model, body, diagnostics));
    } else if (spec.filename == "libgazebo_ros_p3d.so") {
      plugins.push_back(std::make_unique<GroundTruth>(spec, model, diagnostics, seed(spec.name)));
    } else if (spec.filename == "libgazebo_ros_imu.so") {
      plugins.push_back(std::make_unique<Imu>(spec.name, parseImuPluginConfig(spec, model, diagnostics),
                                              context.gravity, seed(spec.name)));
    } else {
      diagnostics.warning(where + " filename [" + spec.filename +
                          "] is not a plugin bullet_sim simulates: ignored");
    }
  }

  for (const auto& sensor : model.sensors) {
    const std::string where = "sensor [" + sensor.name + "] on link [" + sensor.link + "]";
    if (!sensor.plugin) {
      diagnostics.warning(where + " has no <plugin>, so Gazebo publishes nothing from it: ignored");
      continue;
    }
    const std::string& filename = sensor.plugin->filename;
    if ((sensor.type == "ray" || sensor.type == "gpu_ray") && kLaserPlugins.count(filename)) {
      RayLidarConfig config = parseRayLidarConfig(sensor, model, diagnostics);
      const BodyId own = context.ray_body(body.partOf(sensor.link));
      plugins.push_back(std::make_unique<RayLidar>(sensor.name, std::move(config), own, seed(sensor.name)));
    } else if (sensor.type == "imu" && filename == "libgazebo_ros_imu_sensor.so") {
      plugins.push_back(std::make_unique<Imu>(sensor.name, parseImuSensorConfig(sensor, model, diagnostics),
                                              context.gravity, seed(sensor.name)));
    } else {
      diagnostics.warning(where + " of type [" + sensor.type + "] with plugin [" + filename +
                          "] is not simulated by bullet_sim: ignored");
    }
  }
  return plugins;
}

}  // namespace bullet_sim
