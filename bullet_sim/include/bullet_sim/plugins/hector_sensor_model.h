// What hector_gazebo_plugins' IMU and GPS share: their error model and their update timer's tags.
//
// The error model (hector's SensorModel), per axis: reading = value * scaleError + offset + drift + white
// noise. The drift starts at N(0, drift^2) and then follows hector's discrete Gauss-Markov step,
// drift <- exp(-dt f) drift + dt N(0, 2 f drift^2), with f the drift frequency. Tags, under a prefix (accel,
// rate, yaw, velocity; none for the GPS position, whose tags are offset, drift, ...): <prefix>Offset,
// <prefix>Drift, <prefix>DriftFrequency [1/3600 Hz], <prefix>GaussianNoise, <prefix>ScaleError [1]; "x y z"
// for a vector model, one number for a scalar one. Every draw comes from the plugin's seeded noise.
#pragma once

#include <Eigen/Core>

#include <random>
#include <string>

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

/// Reads the model's tags under `prefix` ("" for none). A scalar model (`vector` false) reads one number per
/// tag into x; a vector model reads "x y z".
SensorErrorConfig readSensorError(PluginTags& tags, const std::string& prefix, bool vector);

/// An "x y z" tag (Gazebo reads vectors and roll-pitch-yaw so); `fallback` when it is absent, and an error
/// naming the tag when it is not three numbers.
Eigen::Vector3d readVector3(PluginTags& tags, const std::string& tag, const Eigen::Vector3d& fallback);

/// The link hector's plugin measures: <bodyName>, the root link when absent (Gazebo's canonical link) or,
/// after a warning, when it names no link. `name`, when given, receives the name as written (the default
/// frame_id).
std::string readHectorBody(const DeclarationSource& source, std::string* name = nullptr);

/// hector's update timer: updateRate [Hz] or updatePeriod [s]; `fallback` [Hz] when neither is given.
double readHectorUpdateRate(PluginTags& tags, double fallback);

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
