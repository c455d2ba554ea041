#include "plugins/range_sensor/range_sensor.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

namespace bullet_sim {

namespace {

const TagTable kRangeTags = {
    {"topicName", TagType::kTopic, "range", "", "the topic of the ranges; /range (a global name) when absent",
     "range when absent, relative to the namespace"},
    {"frameName", TagType::kFrame, "the sensor's link", "", "the messages' frame_id; /world when absent",
     "the sensor's link when absent; a name that is no link is a warning, and is still the frame_id"},
    {"radiation", TagType::kText, "ultrasound", "",
     "the message's radiation_type: ultrasound, and any other word infrared",
     "the same, with a warning for a word other than ultrasound or infrared"},
    {"fov", TagType::kPositive, "0.05", "rad",
     "the message's field_of_view only; the rays the sensor casts decide what it sees", ""},
    {"gaussianNoise", TagType::kDeviation, "0", "m",
     "the standard deviation of a zero-mean noise on ranges below the maximum, which are then capped at it",
     "noisy ranges are clamped to [min, max]"},
    {"updateRate", TagType::kRate, "0", "Hz",
     "throttles the plugin below the sensor's <update_rate>; 0: at every sensor update", ""},
    {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
};

}  // namespace

void readRangeRays(const DeclarationSource& source, RangeConfig& config, const std::string& plugin,
                   const std::string& author) {
  const std::string where = source.declaration.where();
  config.rays.link = config.link;
  config.rays.pose = config.pose;
  readRayTags(source.sensor, where, config.rays, source, /*noise_used=*/false);
  if (config.rays.range_max <= config.rays.range_min)
    source.diagnostics.error(where + " <range> <max> must exceed <min>");
  if (config.rays.noise_stddev != 0 || config.rays.noise_mean != 0) {
    std::ostringstream message;  // the one warning about the noise, of any sign
    message << where << " <ray><noise> (stddev " << config.rays.noise_stddev << ", mean "
            << config.rays.noise_mean << ") does not reach " << plugin << "'s range (" << author
            << " plugin reads the rays before the sensor's noise): ignored; use the plugin's <gaussianNoise>";
    source.diagnostics.warning(message.str());
  }
}

void parseRange(const DeclarationSource& source, RangeConfig& config) {
  PluginTags& tags = source.tags;
  readRangeRays(source, config, "libgazebo_ros_range.so", "Gazebo's");
  config.topic = tags.text("topicName");
  config.frame = tags.frame("frameName", config.link);
  const std::string radiation = tags.text("radiation");
  config.infrared = radiation != "ultrasound";
  if (radiation != "ultrasound" && radiation != "infrared") {
    source.diagnostics.warning(tags.where() + " <radiation> must be ultrasound or infrared, not [" +
                               radiation + "]: infrared is used, as Gazebo does");
  }
  config.field_of_view = tags.nonNegative("fov");
  config.noise_stddev = tags.deviation("gaussianNoise");
  frameLink(source, "frameName", config.frame);
}

RangeSensor::RangeSensor(const PluginDeclaration& declaration, const RangeConfig& config,
                         const PluginSetup& setup)
    : RayCastingPlugin(declaration, setup,
                       {config.rays.link, config.rays.pose, rayDirections(config.rays, config.rays.channels),
                        config.rays.range_max}),
      config_(config) {
  RangeSample& sample = samples_.next();
  sample.frame_id = config_.frame;
  sample.infrared = config_.infrared;
  sample.field_of_view = config_.field_of_view;
  sample.min_range = config_.rays.range_min;
  sample.max_range = config_.rays.range_max;
  addOutput(config_.topic, samples_);
}

double RangeSensor::measured(double nearest, double /*sim_time*/) {
  if (nearest < config_.rays.range_min) return -std::numeric_limits<double>::infinity();
  if (!(nearest < config_.rays.range_max)) return config_.rays.range_max;
  if (config_.noise_stddev <= 0) return nearest;
  std::normal_distribution<double> gaussian(0.0, config_.noise_stddev);
  return std::clamp(nearest + gaussian(noise()), config_.rays.range_min, config_.rays.range_max);
}

void RangeSensor::sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) {
  if (!readingDue(time, body, rays)) return;
  RangeSample& sample = samples_.next();
  sample.stamp = time.sim_time;
  sample.range = measured(*std::min_element(ranges().begin(), ranges().end()), time.sim_time);
  samples_.publish();
}

BULLET_SIM_PLUGIN_FOLDER(range_sensor) {
  PluginType type = pluginType<RangeSensor>("libgazebo_ros_range.so", parseRange, kRangeTags);
  type.sensor_types = {"ray"};
  // The plugin throttles the sensor's updates: the slower rate wins.
  type.rate = {RateRule::From::kSlowerOfSensorAndTags, {"updateRate"}, 0};
  type.needs = kNeedOwnRayBody;
  type.tf_prefix = TfPrefixRule::kNamespaceParam;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
