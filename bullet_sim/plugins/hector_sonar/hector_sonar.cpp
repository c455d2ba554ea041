#include "plugins/hector_sonar/hector_sonar.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <cmath>

namespace bullet_sim {

namespace {

TagTable hectorSonarTags() {
  const std::vector<TagRow> own = {
      {"topicName", TagType::kTopic, "sonar", "", "the topic of the sensor_msgs/Range", ""},
      {"frameId", TagType::kFrame, "/sonar_link", "",
       "the messages' frame_id only, as written (no tf_prefix)",
       "the leading / dropped, as on every frame (the default is sonar_link); a name that is no link is a "
       "warning, and is still the frame_id"},
      {"updateRate", TagType::kRate, "10", "Hz",
       "how often it publishes the latest rays, whatever the sensor's <update_rate>; 0: every step",
       "the rays are cast when it publishes"},
      {"updatePeriod", TagType::kNumber, "1 / updateRate", "s",
       "the time between updates, instead of updateRate; 0: every step; below 0: as its absolute value", ""},
      {"updateOffset", TagType::kText, "0", "s", "delays the updates within each period",
       "not honoured: a warning says so"},
  };
  TagTable table;
  for (const auto& rows : {own, sensorErrorRows("", /*vector=*/false, "m")}) {
    for (const TagRow& row : rows) table.add(row);
  }
  return table;
}

}  // namespace

void parseHectorSonar(const DeclarationSource& source, HectorSonarConfig& config) {
  PluginTags& tags = source.tags;
  readRangeRays(source, config, "libhector_gazebo_ros_sonar.so", "hector's");
  config.topic = tags.text("topicName");
  config.frame = tags.frame("frameId", "sonar_link", /*gazebo_drops_slash=*/false);
  frameLink(source, "frameId", config.frame);
  config.update_rate = readHectorUpdateRate(tags);
  config.error = readSensorError(tags, "", /*vector=*/false);
  config.infrared = false;
  // hector's field of view: the narrower of the scan's two spans.
  const RayLidarConfig& rays = config.rays;
  config.field_of_view = std::min(std::abs(rays.max_angle - rays.min_angle),
                                  std::abs(rays.max_elevation - rays.min_elevation));
}

HectorSonar::HectorSonar(const PluginDeclaration& declaration, const HectorSonarConfig& config,
                         const PluginSetup& setup)
    : RangeSensor(declaration, config, setup), error_(config.error) {
  onReset();
}

double HectorSonar::measured(double nearest, double sim_time) {
  const double dt = last_update_ < 0 ? 0 : sim_time - last_update_;
  last_update_ = sim_time;
  const double min = config().rays.range_min, max = config().rays.range_max;
  if (!(nearest < max)) return max;  // nothing within range: the maximum, untouched
  const double read = error_.apply(Eigen::Vector3d(nearest, 0, 0), dt, noise()).x();
  return std::clamp(read, min, max);
}

void HectorSonar::onReset() {
  last_update_ = -1;
  error_.reset(noise());
}

BULLET_SIM_PLUGIN_FOLDER(hector_sonar) {
  PluginType type =
      pluginType<HectorSonar>("libhector_gazebo_ros_sonar.so", parseHectorSonar, hectorSonarTags());
  type.sensor_types = {"ray"};
  type.needs = kNeedOwnRayBody;
  type.tf_prefix = TfPrefixRule::kNone;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
