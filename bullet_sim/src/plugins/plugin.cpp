#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

namespace {
// Sim time is a whole number of steps; this absorbs the rounding of k * dt against a period.
constexpr double kTimeEpsilon = 1e-9;
}  // namespace

bool UpdateTimer::wouldFire(const StepTime& time) const { return time.sim_time + kTimeEpsilon >= next_; }

double UpdateTimer::nextAfter(const StepTime& time) const {
  const double next = next_ + period_;
  // never fire twice in one step
  return next < time.sim_time + kTimeEpsilon ? time.sim_time + period_ : next;
}

bool UpdateTimer::due(const StepTime& time) {
  if (!wouldFire(time)) return false;
  next_ = nextAfter(time);
  return true;
}

Plugin::Plugin(const PluginDeclaration& declaration, const PluginSetup& setup)
    : name_(declaration.displayName()),
      robot_namespace_(setup.robot_namespace.value_or(declaration.config->robot_namespace)),
      where_(declaration.where()),
      tf_prefix_(setup.tf_prefix),
      global_frames_(declaration.config->global_frames),
      timer_(declaration.config->update_rate),
      seed_(setup.seed ^ stableHash(setup.robot_name + "/" + name_)),
      noise_(seed_) {}

void Plugin::reset() {
  timer_.reset();
  noise_.seed(seed_);
  onReset();
}

Eigen::Vector3d Plugin::gaussian3(double stddev) {
  if (stddev <= 0) return Eigen::Vector3d::Zero();
  std::normal_distribution<double> normal(0.0, stddev);
  const double x = normal(noise_), y = normal(noise_), z = normal(noise_);
  return {x, y, z};
}

uint64_t stableHash(const std::string& text) {
  uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace bullet_sim
