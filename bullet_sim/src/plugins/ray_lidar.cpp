#include "bullet_sim/plugins/ray_lidar.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

namespace bullet_sim {

namespace {

const tinyxml2::XMLElement* path(const tinyxml2::XMLElement* element,
                                 std::initializer_list<const char*> names) {
  for (const char* name : names) element = element ? element->FirstChildElement(name) : nullptr;
  return element;
}

}  // namespace

int RayLidarConfig::beams() const { return std::max(1, static_cast<int>(std::lround(samples * resolution))); }

RayLidarConfig parseRayLidarConfig(const SensorSpec& sensor, const ModelSpec& model,
                                   Diagnostics& diagnostics) {
  RayLidarConfig config;
  config.link = sensor.link;
  config.pose = sensor.pose;
  config.update_rate = sensor.update_rate;
  config.frame = sensor.link;
  const std::string where = "sensor [" + sensor.name + "] on link [" + sensor.link + "]";

  PluginTags horizontal(path(sensor.element, {"ray", "scan", "horizontal"}), where + " <horizontal>",
                        diagnostics);
  config.samples = static_cast<int>(horizontal.positive("samples", 640));
  config.resolution = horizontal.positive("resolution", 1);
  config.min_angle = horizontal.number("min_angle", 0);
  config.max_angle = horizontal.number("max_angle", 0);
  horizontal.finish();
  if (config.max_angle < config.min_angle)
    diagnostics.error(where + " <horizontal> <max_angle> is below <min_angle>");

  if (const auto* vertical_element = path(sensor.element, {"ray", "scan", "vertical"})) {
    PluginTags vertical(vertical_element, where + " <vertical>", diagnostics);
    config.channels = std::max(1, static_cast<int>(std::lround(vertical.positive("samples", 1) *
                                                               vertical.positive("resolution", 1))));
    config.min_elevation = vertical.number("min_angle", 0);
    config.max_elevation = vertical.number("max_angle", 0);
    vertical.finish();
    if (config.max_elevation < config.min_elevation) {
      diagnostics.error(where + " <vertical> <max_angle> is below <min_angle>");
    }
  }

  PluginTags range(path(sensor.element, {"ray", "range"}), where + " <range>", diagnostics);
  config.range_min = range.positive("min", 0, /*allow_zero=*/true);
  config.range_max = range.positive("max", 0);
  range.accept({"resolution"});  // Gazebo's ray sensor does not quantise its ranges either
  range.finish();

  if (const auto* noise_element = path(sensor.element, {"ray", "noise"})) {
    PluginTags noise(noise_element, where + " <noise>", diagnostics);
    const std::string type = noise.text("type", "gaussian");
    if (type != "gaussian" && type != "none") {
      diagnostics.error(where + " <noise><type> must be gaussian or none, not [" + type + "]");
    }
    config.noise_mean = noise.number("mean", 0);
    config.noise_stddev = noise.positive("stddev", 0, /*allow_zero=*/true);
    if (type == "none") config.noise_mean = config.noise_stddev = 0;
    noise.finish();
  }

  if (sensor.plugin) {
    const std::string& filename = sensor.plugin->filename;
    const bool velodyne = filename.find("velodyne") != std::string::npos;
    config.output = velodyne                                     ? RayLidarConfig::Output::kPointCloud2
                    : filename == "libgazebo_ros_block_laser.so" ? RayLidarConfig::Output::kPointCloud
                                                                 : RayLidarConfig::Output::kLaserScan;
    PluginTags tags(sensor.plugin->element, where + " plugin [" + sensor.plugin->name + "]", diagnostics);
    config.topic = tags.text("topicName", config.topic);
    config.frame = tags.text("frameName", config.frame);
    config.robot_namespace = tags.text("robotNamespace", "");
    if (velodyne) {
      config.range_min = tags.positive("min_range", config.range_min, /*allow_zero=*/true);
      config.range_max = tags.positive("max_range", config.range_max);
      if (tags.has("gaussianNoise")) {
        config.noise_mean = 0;
        config.noise_stddev = tags.positive("gaussianNoise", 0, /*allow_zero=*/true);
      }
    }
    tags.accept({"gaussianNoise", "hokuyoMinIntensity", "updateRate", "alwaysOn", "organize_cloud"});
    tags.finish();
  }
  if (config.range_max <= config.range_min) diagnostics.error(where + " <range> <max> must exceed <min>");
  if (!model.link(config.frame)) {
    diagnostics.error(where + " <frameName> [" + config.frame + "] is not a link" +
                      didYouMean(config.frame, model.linkNames()) +
                      "; Gazebo would publish scans in a frame tf lacks");
  }
  return config;
}

RayLidar::RayLidar(std::string name, RayLidarConfig config, BodyId own_body, uint64_t seed)
    : Plugin(std::move(name)),
      config_(std::move(config)),
      own_body_(own_body),
      seed_(seed),
      timer_(config_.update_rate),
      noise_(seed) {
  const int beams = config_.beams();
  const double increment = beams > 1 ? (config_.max_angle - config_.min_angle) / (beams - 1) : 0.0;
  // A LaserScan is the plane at 0 elevation; point clouds take every channel, bottom first.
  const int channels = config_.output == RayLidarConfig::Output::kLaserScan ? 1 : config_.channels;
  const double elevation_step =
      channels > 1 ? (config_.max_elevation - config_.min_elevation) / (channels - 1) : 0.0;
  for (int channel = 0; channel < channels; ++channel) {
    const double elevation = channels > 1 ? config_.min_elevation + channel * elevation_step : 0.0;
    for (int i = 0; i < beams; ++i) {
      const double angle = config_.min_angle + i * increment;
      directions_.emplace_back(std::cos(elevation) * std::cos(angle), std::cos(elevation) * std::sin(angle),
                               std::sin(elevation));
    }
  }
  world_directions_.resize(directions_.size());
  ranges_.resize(directions_.size());
  scan_.frame_id = cloud_.frame_id = config_.frame;
  scan_.angle_min = config_.min_angle;
  scan_.angle_max = config_.max_angle;
  scan_.angle_increment = increment;
  scan_.scan_time = config_.update_rate > 0 ? 1.0 / config_.update_rate : 0.0;
  scan_.range_min = config_.range_min;
  scan_.range_max = config_.range_max;
  if (config_.output == RayLidarConfig::Output::kLaserScan) scan_.ranges.resize(beams);
}

void RayLidar::sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) {
  if (!timer_.due(time)) return;
  const Eigen::Isometry3d sensor = body.linkPose(config_.link) * config_.pose;
  const Eigen::Matrix3f rotation = sensor.linear().cast<float>();
  for (size_t i = 0; i < directions_.size(); ++i) world_directions_[i] = rotation * directions_[i];
  rays.cast(sensor.translation(), world_directions_, config_.range_max, own_body_, ranges_);

  std::normal_distribution<double> gaussian(config_.noise_mean, config_.noise_stddev);
  const bool noisy = config_.noise_stddev > 0 || config_.noise_mean != 0;
  const auto measured = [&](double range) {
    if (range < config_.range_min) return -std::numeric_limits<double>::infinity();
    if (std::isfinite(range) && noisy)
      return std::clamp(range + gaussian(noise_), config_.range_min, config_.range_max);
    return range;
  };
  if (config_.output == RayLidarConfig::Output::kLaserScan) {
    for (size_t i = 0; i < ranges_.size(); ++i) scan_.ranges[i] = static_cast<float>(measured(ranges_[i]));
    scan_.stamp = time.sim_time;
    scan_.sensor_pose = sensor;
  } else {
    cloud_.points.clear();
    cloud_.rings.clear();
    const size_t beams = static_cast<size_t>(config_.beams());
    for (size_t i = 0; i < ranges_.size(); ++i) {
      const double range = measured(ranges_[i]);
      if (!std::isfinite(range)) continue;
      cloud_.points.push_back(directions_[i] * static_cast<float>(range));
      cloud_.rings.push_back(static_cast<uint16_t>(i / beams));
    }
    cloud_.intensities.assign(cloud_.points.size(), 1.0f);
    cloud_.stamp = time.sim_time;
    cloud_.sensor_pose = sensor;
  }
  ++scan_count_;
}

void RayLidar::reset() {
  timer_.reset();
  noise_.seed(seed_);
}

}  // namespace bullet_sim
