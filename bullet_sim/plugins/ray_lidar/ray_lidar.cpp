#include "plugins/ray_lidar/ray_lidar.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>

namespace bullet_sim {

namespace {

/// The <samples> and <resolution> of a <horizontal> or <vertical> block; samples are whole.
struct Sampling {
  double samples = 1;
  double resolution = 1;
  double beams() const { return std::max(1.0, std::round(samples * resolution)); }
};

Sampling samplingOf(PluginTags& tags, double default_samples, const std::string& where,
                    Diagnostics& diagnostics) {
  Sampling sampling{tags.positive("samples", default_samples), tags.positive("resolution", 1)};
  if (sampling.samples != std::floor(sampling.samples)) {
    std::ostringstream message;
    message << where << " <samples> must be a whole number, not " << sampling.samples;
    diagnostics.error(message.str());
  }
  return sampling;
}

/// The rays of a scan within the limit, so that no sensor asks for gigabytes: an error otherwise.
bool withinRayLimit(double beams, double channels, const std::string& where, const Limits& limits,
                    Diagnostics& diagnostics) {
  const double limit = std::min<double>(limits.max_rays, std::numeric_limits<int>::max());
  if (beams * channels <= limit) return true;
  std::ostringstream message;
  message << std::setprecision(17) << where << " asks for " << beams << " beams x " << channels
          << " channels = " << beams * channels << " rays per scan, above the limit of " << limit
          << " (max_rays): use fewer <samples> or a lower "
          << "<resolution>";
  diagnostics.error(message.str());
  return false;
}

/// Gazebo's ray sensor takes a <max_angle> below <min_angle>: its rays step from min_angle down to max_angle,
/// and so do ours (a LaserScan's angle_increment is then negative).
void warnDescending(const std::string& where, const char* rays, Diagnostics& diagnostics) {
  diagnostics.warning(where + " <max_angle> is below <min_angle>: the " + rays +
                      " step from min_angle down to max_angle, as Gazebo's do");
}

}  // namespace

void readRayTags(const TagNode* sensor, const std::string& where, RayLidarConfig& config,
                 const DeclarationSource& source, bool noise_used) {
  Diagnostics& diagnostics = source.diagnostics;
  const TagNode* ray = sensor ? sensor->child("ray") : nullptr;
  PluginTags horizontal(ray ? ray->find({"scan", "horizontal"}) : nullptr, where + " <horizontal>",
                        diagnostics);
  const Sampling sampling = samplingOf(horizontal, 640, where + " <horizontal>", diagnostics);
  config.min_angle = horizontal.number("min_angle", 0);
  config.max_angle = horizontal.number("max_angle", 0);
  horizontal.finish();
  if (config.max_angle < config.min_angle) warnDescending(where + " <horizontal>", "beams", diagnostics);

  double channels = 1;
  if (const TagNode* vertical_node = ray ? ray->find({"scan", "vertical"}) : nullptr) {
    PluginTags vertical(vertical_node, where + " <vertical>", diagnostics);
    channels = samplingOf(vertical, 1, where + " <vertical>", diagnostics).beams();
    config.min_elevation = vertical.number("min_angle", 0);
    config.max_elevation = vertical.number("max_angle", 0);
    vertical.finish();
    if (config.max_elevation < config.min_elevation)
      warnDescending(where + " <vertical>", "channels", diagnostics);
  }
  // The samples count too: a fine resolution must not shrink 10^12 samples into one beam.
  if (withinRayLimit(std::max(sampling.beams(), sampling.samples), channels, where, source.limits,
                     diagnostics)) {
    config.samples = static_cast<int>(sampling.samples);
    config.resolution = sampling.resolution;
    config.channels = static_cast<int>(channels);
  }

  PluginTags range(ray ? ray->child("range") : nullptr, where + " <range>", diagnostics);
  config.range_min = range.positive("min", 0, /*allow_zero=*/true);
  config.range_max = range.capped("max", 0, source.limits.max_length, "max_length", "m");
  range.accept({"resolution"});  // Gazebo's ray sensor does not quantise its ranges either
  range.finish();

  if (const TagNode* noise_node = ray ? ray->child("noise") : nullptr) {
    PluginTags noise(noise_node, where + " <noise>", diagnostics);
    const std::string type = noise.text("type", "gaussian");
    if (type != "gaussian" && type != "none") {
      diagnostics.error(where + " <noise><type> must be gaussian or none, not [" + type + "]");
    }
    config.noise_mean = noise.number("mean", 0);
    config.noise_stddev = noise_used ? noise.deviation("stddev", 0) : noise.number("stddev", 0);
    if (type == "none") config.noise_mean = config.noise_stddev = 0;
    noise.finish();
  }
}

namespace {

RayLidarConfig::Output outputOf(const std::string& filename) {
  if (filename.find("velodyne") != std::string::npos) return RayLidarConfig::Output::kPointCloud2;
  if (filename == "libgazebo_ros_block_laser.so") return RayLidarConfig::Output::kPointCloud;
  return RayLidarConfig::Output::kLaserScan;
}

/// The velodyne plugins' own tags: a range band and a noise that replace the sensor's.
void readVelodyneTags(PluginTags& tags, RayLidarConfig& config) {
  config.range_min = tags.positive("min_range", config.range_min, /*allow_zero=*/true);
  config.range_max = tags.positive("max_range", config.range_max);
  if (tags.has("gaussianNoise")) config.noise_mean = 0;
  config.noise_stddev = tags.deviation("gaussianNoise", config.noise_stddev);
}

/// The plugin tags of a lidar of `output`: those every laser plugin shares, then the velodyne plugins' own.
TagTable lidarTags(RayLidarConfig::Output output) {
  const bool velodyne = output == RayLidarConfig::Output::kPointCloud2;
  const bool block = output == RayLidarConfig::Output::kPointCloud;
  TagTable table{
      {"topicName", TagType::kTopic, "scan", "",
       velodyne ? "the topic of the clouds; /points (a global name) when absent"
                : "the topic of its messages; /world when absent, a name no one listens to",
       "scan when absent, relative to the namespace"},
      {"frameName", TagType::kFrame, "the sensor's link", "", "the messages' frame_id; /world when absent",
       "the sensor's link when absent; a name that is no link is a warning, and is still the frame_id"},
      {"updateRate", TagType::kIgnored, "", "Hz",
       block ? "read, and never used: the sensor's <update_rate> sets the pace" : "not read",
       "the sensor's <update_rate> sets the pace"},
      {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
      {"hokuyoMinIntensity", TagType::kIgnored, "", "",
       block ? "read (101 when absent) and used in no message" : "not read (block_laser's tag)", ""},
      {"organize_cloud", TagType::kIgnored, "", "",
       velodyne ? "true keeps every ray in a width x height cloud, NaN where nothing is in range; false when "
                  "absent"
                : "not read (the velodyne plugins' tag)",
       velodyne ? "the cloud holds the in-range returns only, as with false" : ""},
  };
  if (!velodyne) {
    table.add({"gaussianNoise", TagType::kIgnored, "", "m",
               block ? "the standard deviation of a noise on each point's x, y and z, and on its intensity"
                     : "not read (block_laser's and the velodyne plugins' tag)",
               block ? "not applied: give the sensor a <ray><noise> instead" : ""});
    return table;
  }
  table.add({"min_range", TagType::kPositive, "the sensor's <range><min>", "m",
             "returns at or below the larger of it and the sensor's <min> are left out; 0 when absent",
             "replaces the sensor's <min>: returns below it are left out"});
  table.add({"max_range", TagType::kPositive, "the sensor's <range><max>", "m",
             "returns at or beyond the smaller of it and the sensor's <max> are left out; none when absent",
             "replaces the sensor's <max>: rays reach it, and returns beyond it are left out"});
  table.add({"gaussianNoise", TagType::kDeviation, "the sensor's <noise>", "m",
             "the standard deviation of a zero-mean noise on each kept range; 0 when absent",
             "replaces the sensor's <noise>; noisy ranges are clamped to the range band"});
  return table;
}

}  // namespace

int RayLidarConfig::beams() const { return std::max(1, static_cast<int>(std::lround(samples * resolution))); }

std::vector<Eigen::Vector3f> rayDirections(const RayLidarConfig& config, int channels) {
  const int beams = config.beams();
  const double increment = beams > 1 ? (config.max_angle - config.min_angle) / (beams - 1) : 0.0;
  const double elevation_step =
      channels > 1 ? (config.max_elevation - config.min_elevation) / (channels - 1) : 0.0;
  std::vector<Eigen::Vector3f> directions;
  for (int channel = 0; channel < channels; ++channel) {
    const double elevation = channels > 1 ? config.min_elevation + channel * elevation_step : 0.0;
    for (int i = 0; i < beams; ++i) {
      const double angle = config.min_angle + i * increment;
      directions.emplace_back(std::cos(elevation) * std::cos(angle), std::cos(elevation) * std::sin(angle),
                              std::sin(elevation));
    }
  }
  return directions;
}

void parseRayLidar(const DeclarationSource& source, RayLidarConfig& config) {
  const std::string where = source.declaration.where();
  readRayTags(source.sensor, where, config, source);
  PluginTags& tags = source.tags;
  config.output = outputOf(source.declaration.filename);
  config.topic = tags.text("topicName");
  config.frame = tags.frame("frameName", config.link);
  if (config.output == RayLidarConfig::Output::kPointCloud2) readVelodyneTags(tags, config);
  if (config.range_max <= config.range_min)
    source.diagnostics.error(where + " <range> <max> must exceed <min>");
  frameLink(source, "frameName", config.frame);
}

namespace {

/// A LaserScan is the plane at 0 elevation; point clouds take every channel, bottom first.
RayAim lidarAim(const RayLidarConfig& config) {
  const bool planar = config.output == RayLidarConfig::Output::kLaserScan;
  return {config.link, config.pose, rayDirections(config, planar ? 1 : config.channels), config.range_max};
}

}  // namespace

RayLidar::RayLidar(const PluginDeclaration& declaration, const RayLidarConfig& config,
                   const PluginSetup& setup)
    : RayCastingPlugin(declaration, setup, lidarAim(config)), config_(config) {
  const int beams = config_.beams();
  const double increment = beams > 1 ? (config_.max_angle - config_.min_angle) / (beams - 1) : 0.0;
  LaserScan& scan = scan_.next();
  scan.frame_id = cloud_.next().frame_id = legacy_cloud_.next().frame_id = config_.frame;
  scan.angle_min = config_.min_angle;
  scan.angle_max = config_.max_angle;
  scan.angle_increment = increment;
  scan.scan_time = config_.update_rate > 0 ? 1.0 / config_.update_rate : 0.0;
  scan.range_min = config_.range_min;
  scan.range_max = config_.range_max;
  switch (config_.output) {
    case RayLidarConfig::Output::kLaserScan:
      scan.ranges.resize(beams);
      addOutput(config_.topic, scan_);
      break;
    case RayLidarConfig::Output::kPointCloud2:
      addOutput(config_.topic, cloud_);
      break;
    case RayLidarConfig::Output::kPointCloud:
      addOutput(config_.topic, legacy_cloud_);
      break;
  }
}

double RayLidar::measured(double range, std::normal_distribution<double>& gaussian) {
  if (range < config_.range_min) return -std::numeric_limits<double>::infinity();
  const bool noisy = config_.noise_stddev > 0 || config_.noise_mean != 0;
  if (std::isfinite(range) && noisy)
    return std::clamp(range + gaussian(noise()), config_.range_min, config_.range_max);
  return range;
}

void RayLidar::sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) {
  if (!readingDue(time, body, rays)) return;
  if (config_.output == RayLidarConfig::Output::kLaserScan) {
    publishScan(time);
  } else {
    publishCloud(time);
  }
}

void RayLidar::publishScan(const StepTime& time) {
  std::normal_distribution<double> gaussian(config_.noise_mean, config_.noise_stddev);
  LaserScan& scan = scan_.next();
  for (size_t i = 0; i < ranges().size(); ++i)
    scan.ranges[i] = static_cast<float>(measured(ranges()[i], gaussian));
  scan.stamp = time.sim_time;
  scan.sensor_pose = sensorPose();
  scan_.publish();
}

void RayLidar::publishCloud(const StepTime& time) {
  std::normal_distribution<double> gaussian(config_.noise_mean, config_.noise_stddev);
  const bool legacy = config_.output == RayLidarConfig::Output::kPointCloud;
  PointCloud& cloud = legacy ? legacy_cloud_.next() : cloud_.next();
  cloud.points.clear();
  cloud.rings.clear();
  const size_t beams = static_cast<size_t>(config_.beams());
  for (size_t i = 0; i < ranges().size(); ++i) {
    const double range = measured(ranges()[i], gaussian);
    if (!std::isfinite(range)) continue;
    cloud.points.push_back(directions()[i] * static_cast<float>(range));
    cloud.rings.push_back(static_cast<uint16_t>(i / beams));
  }
  cloud.intensities.assign(cloud.points.size(), 1.0f);
  cloud.stamp = time.sim_time;
  cloud.sensor_pose = sensorPose();
  legacy ? legacy_cloud_.publish() : cloud_.publish();
}

BULLET_SIM_PLUGIN_FOLDER(ray_lidar) {
  for (const char* filename :
       {"libgazebo_ros_laser.so", "libgazebo_ros_gpu_laser.so", "libgazebo_ros_velodyne_laser.so",
        "libgazebo_ros_velodyne_gpu_laser.so", "libgazebo_ros_block_laser.so"}) {
    PluginType type = pluginType<RayLidar>(filename, parseRayLidar, lidarTags(outputOf(filename)));
    type.sensor_types = {"ray", "gpu_ray"};
    type.rate = {RateRule::From::kSensor, {"updateRate"}, 0};
    type.needs = kNeedOwnRayBody;
    // gazebo_ros_laser and gpu_laser search tf_prefix up from their namespace; the block laser and
    // velodyne_simulator's plugins read <namespace>/tf_prefix only.
    const std::string name = filename;
    if (name != "libgazebo_ros_laser.so" && name != "libgazebo_ros_gpu_laser.so")
      type.tf_prefix = TfPrefixRule::kNamespaceParam;
    registrar.add(std::move(type));
  }
}

}  // namespace bullet_sim
