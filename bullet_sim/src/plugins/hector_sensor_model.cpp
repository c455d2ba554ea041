#include "bullet_sim/plugins/hector_sensor_model.h"

#include <cctype>
#include <cmath>
#include <sstream>

namespace bullet_sim {

namespace {

/// A sample of N(0, stddev^2); zero, drawing nothing, when `stddev` is 0.
double gaussian(double stddev, std::mt19937_64& noise) {
  if (stddev <= 0) return 0;
  return std::normal_distribution<double>(0.0, stddev)(noise);
}

/// "x y z" (a vector model) or one number (a scalar one, into x).
Eigen::Vector3d readValues(PluginTags& tags, const std::string& tag, const Eigen::Vector3d& fallback,
                           bool vector) {
  if (!tags.has(tag)) return fallback;
  if (!vector) return {tags.number(tag, fallback.x()), 0, 0};
  return readVector3(tags, tag, fallback);
}

}  // namespace

Eigen::Vector3d readVector3(PluginTags& tags, const std::string& tag, const Eigen::Vector3d& fallback) {
  if (!tags.has(tag)) return fallback;
  const std::string text = tags.text(tag, "");
  std::istringstream in(text);
  Eigen::Vector3d value;
  std::string rest;
  if (!(in >> value.x() >> value.y() >> value.z()) || (in >> rest) || !value.allFinite()) {
    tags.diagnostics().error(tags.where() + " <" + tag + "> must be three numbers (x y z), not [" + text +
                             "]");
    return fallback;
  }
  return value;
}

SensorErrorConfig readSensorError(PluginTags& tags, const std::string& prefix, bool vector) {
  const auto name = [&](const std::string& field) {
    if (prefix.empty()) return std::string(1, static_cast<char>(std::tolower(field[0]))) + field.substr(1);
    return prefix + field;
  };
  SensorErrorConfig config;
  config.offset = readValues(tags, name("Offset"), config.offset, vector);
  config.drift = readValues(tags, name("Drift"), config.drift, vector);
  config.drift_frequency = readValues(tags, name("DriftFrequency"), config.drift_frequency, vector);
  config.gaussian_noise = readValues(tags, name("GaussianNoise"), config.gaussian_noise, vector);
  config.scale_error = readValues(tags, name("ScaleError"), config.scale_error, vector);
  const int axes = vector ? 3 : 1;
  if ((config.drift.head(axes).array() < 0).any() || (config.gaussian_noise.head(axes).array() < 0).any() ||
      (config.drift_frequency.head(axes).array() < 0).any()) {
    tags.diagnostics().error(tags.where() + " <" + name("Drift") + ">, <" + name("DriftFrequency") +
                             "> and <" + name("GaussianNoise") + "> must not be negative");
  }
  return config;
}

std::string readHectorBody(const DeclarationSource& source, std::string* name) {
  const std::string body = source.tags.frame("bodyName", source.model.root, /*gazebo_drops_slash=*/false);
  if (name) *name = body;
  return frameLink(source, "bodyName", body, source.model.root);
}

double readHectorUpdateRate(PluginTags& tags, double fallback) {
  double rate = tags.positive("updateRate", fallback, /*allow_zero=*/true);
  if (tags.has("updatePeriod")) {
    const double period = tags.positive("updatePeriod", 0, /*allow_zero=*/true);
    rate = period > 0 ? 1 / period : 0;
  }
  if (tags.has("updateOffset")) {
    tags.text("updateOffset", "");
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
