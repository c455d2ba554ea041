// What hector_gazebo_plugins' IMU and GPS share: their error model, their body and update timer tags.
//
// The error model (hector's SensorModel), per axis: reading = value * scaleError + offset + drift + white
// noise. The drift starts at N(0, drift^2) and then follows hector's discrete Gauss-Markov step,
// drift <- exp(-dt f) drift + dt N(0, 2 f drift^2), with f the drift frequency. Its tags (sensorErrorRows) go
// under a prefix (accel, rate, yaw, velocity; none for the GPS position). Every draw comes from the plugin's
// seeded noise.
#pragma once

#include <Eigen/Core>

#include <random>
#include <string>
#include <vector>

#include "bullet_sim/model/model.h"
#include "bullet_sim/model/plugin_tags.h"

namespace bullet_sim {

struct SensorErrorConfig {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  Eigen::Vector3d drift = Eigen::Vector3d::Zero();  ///< standard deviation of the drift
  Eigen::Vector3d drift_frequency = Eigen::Vector3d::Constant(1.0 / 3600);  ///< [Hz]
  Eigen::Vector3d gaussian_noise = Eigen::Vector3d::Zero();                 ///< standard deviation
  Eigen::Vector3d scale_error = Eigen::Vector3d::Ones();
};

/// The tag rows of the model under `prefix` ("" for none): "x y z" tags for a vector model, one number for a
/// scalar one; `unit` is its readings'.
std::vector<TagRow> sensorErrorRows(const std::string& prefix, bool vector, const std::string& unit);

/// Reads the model's tags under `prefix` ("" for none) through the plugin's tag table, which holds
/// sensorErrorRows(prefix, vector, ...). A scalar model (`vector` false) reads one number per tag into x.
SensorErrorConfig readSensorError(PluginTags& tags, const std::string& prefix, bool vector);

/// An "x y z" tag (Gazebo reads vectors and roll-pitch-yaw so); when absent, its table row's default (three
/// numbers, or one for every axis). An error names the tag when it is not three numbers.
Eigen::Vector3d readVector3(PluginTags& tags, const std::string& tag);

/// The rows of what hector's IMU and GPS read alike: bodyName and their update timer (updateRate, whose
/// default is `rate` [Hz], updatePeriod and updateOffset).
std::vector<TagRow> hectorBodyAndTimerRows(const std::string& rate);

/// The link hector's plugin measures: <bodyName>, the root link when absent (Gazebo's canonical link) or,
/// after a warning, when it names no link. `name`, when given, receives the name as written (the default
/// frame_id).
std::string readHectorBody(const DeclarationSource& source, std::string* name = nullptr);

/// hector's update timer: updateRate [Hz] or updatePeriod [s].
double readHectorUpdateRate(PluginTags& tags);

/// The error model's state: its drift. Scalar models use x.
class SensorError {
 public:
  explicit SensorError(const SensorErrorConfig& config) : config_(config) {}

  /// A new initial drift, drawn as hector does at load and on reset.
  void reset(std::mt19937_64& noise);
  /// Advances the drift by `dt` [s] and returns `value` as the sensor reads it.
  Eigen::Vector3d apply(const Eigen::Vector3d& value, double dt, std::mt19937_64& noise);

  /// offset + drift: the error without white noise.
  Eigen::Vector3d bias() const { return config_.offset + drift_; }
  const Eigen::Vector3d& drift() const { return drift_; }
  void setDrift(const Eigen::Vector3d& drift) { drift_ = drift; }
  const SensorErrorConfig& config() const { return config_; }

 private:
  SensorErrorConfig config_;
  Eigen::Vector3d drift_ = Eigen::Vector3d::Zero();
};

}  // namespace bullet_sim
