#include "bullet_sim/plugins/hector_sensor_model.h"

#include <cctype>
#include <cmath>
#include <optional>
#include <sstream>

namespace bullet_sim {

namespace {

/// A sample of N(0, stddev^2); zero, drawing nothing, when `stddev` is 0.
double gaussian(double stddev, std::mt19937_64& noise) {
  if (stddev <= 0) return 0;
  return std::normal_distribution<double>(0.0, stddev)(noise);
}

/// Three finite numbers and nothing more, or nullopt.
std::optional<Eigen::Vector3d> threeNumbers(const std::string& text) {
  std::istringstream in(text);
  Eigen::Vector3d value;
  std::string rest;
  if (!(in >> value.x() >> value.y() >> value.z()) || (in >> rest) || !value.allFinite()) return std::nullopt;
  return value;
}

/// The name of the model's tag `field` ("Offset", ...) under `prefix`: accelOffset, or offset without one.
std::string modelTag(const std::string& prefix, const std::string& field) {
  if (prefix.empty()) return std::string(1, static_cast<char>(std::tolower(field[0]))) + field.substr(1);
  return prefix + field;
}

/// A negative component of `noise` is read as its absolute value, with a warning naming both and ending in
/// `reason`. `axes`: how many of `noise`'s components were read.
void readAbsolute(PluginTags& tags, const std::string& tag, int axes, Eigen::Vector3d& noise,
                  const char* reason) {
  if (!(noise.head(axes).array() < 0).any()) return;
  std::ostringstream message;
  const auto write = [&](const Eigen::Vector3d& value) {
    for (int i = 0; i < axes; ++i) message << (i ? " " : "") << value[i];
  };
  message << tags.where() << " <" << tag << "> ";
  write(noise);
  message << (axes == 1 ? " is negative" : " has a negative component") << ": read as ";
  noise = noise.cwiseAbs();
  write(noise);
  message << reason;
  tags.diagnostics().warning(message.str());
}

}  // namespace

std::vector<TagRow> sensorErrorRows(const std::string& prefix, bool vector, const std::string& unit) {
  const TagType type = vector ? TagType::kText : TagType::kNumber;
  const std::string form = vector ? "x y z: " : "";
  const std::string seeded = "drawn from the plugin's seeded noise";
  return {
      {modelTag(prefix, "Offset"), type, "0", unit, form + "a constant error on every reading", ""},
      {modelTag(prefix, "Drift"), type, "0", unit,
       form + "the standard deviation of a slowly wandering error (first-order Gauss-Markov), drawn anew at "
              "load and at every reset",
       seeded},
      {modelTag(prefix, "DriftFrequency"), type, "0.0002777777777777778", "Hz",
       form + "how fast the drift wanders: 1/3600 Hz (one hour) when absent; below 0: NaN readings",
       "below 0: its absolute value, with a warning"},
      {modelTag(prefix, "GaussianNoise"), type, "0", unit,
       form + "the standard deviation of a white noise on every reading", seeded},
      {modelTag(prefix, "ScaleError"), type, "1", "", form + "a factor on the true value", ""},
  };
}

Eigen::Vector3d readVector3(PluginTags& tags, const std::string& tag) {
  const bool given = tags.has(tag);
  const std::string text = tags.text(tag);  // absent: the row's default
  if (const auto value = threeNumbers(text)) return *value;
  if (!given) return Eigen::Vector3d::Constant(std::stod(text));  // one default for every axis
  tags.diagnostics().error(tags.where() + " <" + tag + "> must be three numbers (x y z), not [" + text + "]");
  return Eigen::Vector3d::Zero();
}

SensorErrorConfig readSensorError(PluginTags& tags, const std::string& prefix, bool vector) {
  const auto read = [&](const std::string& field) -> Eigen::Vector3d {
    const std::string tag = modelTag(prefix, field);
    return vector ? readVector3(tags, tag) : Eigen::Vector3d(tags.number(tag), 0, 0);
  };
  SensorErrorConfig config;
  config.offset = read("Offset");
  config.drift = read("Drift");
  config.drift_frequency = read("DriftFrequency");
  config.gaussian_noise = read("GaussianNoise");
  config.scale_error = read("ScaleError");
  const int axes = vector ? 3 : 1;
  // hector draws both noises as sigma * X + mu (Box-Muller, X standard normal): any sign of sigma.
  const char* as_gazebo = ", as Gazebo's Gaussian noise takes it";
  readAbsolute(tags, modelTag(prefix, "Drift"), axes, config.drift, as_gazebo);
  readAbsolute(tags, modelTag(prefix, "GaussianNoise"), axes, config.gaussian_noise, as_gazebo);
  // Its drift's sigma is sqrt(2 * frequency) * drift: NaN below 0, and exp(-dt * frequency) grows.
  readAbsolute(tags, modelTag(prefix, "DriftFrequency"), axes, config.drift_frequency,
               " (hector's drift would be NaN: it draws with sqrt(2 * frequency) * drift)");
  return config;
}

std::vector<TagRow> hectorBodyAndTimerRows(const std::string& rate) {
  return {
      {"bodyName", TagType::kFrame, "the root link", "",
       "the link measured; the model's canonical link when absent",
       "a name that is no link is a warning, and the root link is measured"},
      {"updateRate", TagType::kRate, rate, "Hz", "how often it publishes; 0: every step", ""},
      {"updatePeriod", TagType::kNumber, "1 / updateRate", "s",
       "the time between updates, instead of updateRate; 0: every step; below 0: as its absolute value", ""},
      {"updateOffset", TagType::kText, "0", "s", "delays the updates within each period",
       "not honoured: a warning says so"},
  };
}

std::string readHectorBody(const DeclarationSource& source, std::string* name) {
  const std::string body = source.tags.frame("bodyName", source.model.root, /*gazebo_drops_slash=*/false);
  if (name) *name = body;
  return frameLink(source, "bodyName", body, source.model.root);
}

namespace {

/// updatePeriod [s]. hector's UpdateTimer::checkUpdate updates when fmod(time, period) falls within a step,
/// so a negative period is its absolute value: read so, with a warning naming both.
double readHectorUpdatePeriod(PluginTags& tags, double fallback) {
  const double period = tags.number("updatePeriod", fallback);
  if (!(period < 0)) return period;
  std::ostringstream message;
  message << tags.where() << " <updatePeriod> " << period << " s is below 0: read as " << -period
          << " s, as hector's update timer takes it (fmod of the time by the period ignores its sign)";
  tags.diagnostics().warning(message.str());
  return -period;
}

}  // namespace

double readHectorUpdateRate(PluginTags& tags) {
  double rate = tags.rate("updateRate");
  if (tags.has("updatePeriod")) {
    const double period = readHectorUpdatePeriod(tags, rate > 0 ? 1 / rate : 0);
    rate = period > 0 ? 1 / period : 0;
  }
  if (tags.has("updateOffset")) {
    tags.text("updateOffset");
    tags.diagnostics().warning(tags.where() +
                               " <updateOffset> is not honoured: updates come one period after the start");
  }
  return rate;
}

void SensorError::reset(std::mt19937_64& noise) {
  for (int i = 0; i < 3; ++i) drift_[i] = gaussian(config_.drift[i], noise);
}

Eigen::Vector3d SensorError::apply(const Eigen::Vector3d& value, double dt, std::mt19937_64& noise) {
  Eigen::Vector3d error;
  for (int i = 0; i < 3; ++i) {
    const double frequency = config_.drift_frequency[i];
    drift_[i] = std::exp(-dt * frequency) * drift_[i] +
                dt * gaussian(std::sqrt(2 * frequency) * config_.drift[i], noise);
    error[i] = config_.offset[i] + drift_[i] + gaussian(config_.gaussian_noise[i], noise);
  }
  return value.cwiseProduct(config_.scale_error) + error;
}

}  // namespace bullet_sim
