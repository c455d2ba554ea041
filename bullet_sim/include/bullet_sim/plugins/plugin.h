// Plugins: Gazebo plugin and sensor behaviour, ROS-free. Each step runs in three phases: every plugin applies
// its commands, physics steps, then every plugin senses the stepped world, which it may only read.
#pragma once

#include <tinyxml2.h>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "bullet_sim/physics/robot_body.h"
#include "bullet_sim/sensing/ray_caster.h"
#include "bullet_sim/spec/diagnostics.h"
#include "bullet_sim/spec/model_spec.h"

namespace bullet_sim {

/// The step being simulated: it ends at `sim_time` [s] and lasts `dt` [s]. Nothing in the core reads a clock.
struct StepTime {
  double sim_time = 0;
  double dt = 0;
};

class Plugin {
 public:
  explicit Plugin(std::string name) : name_(std::move(name)) {}
  virtual ~Plugin() = default;

  const std::string& name() const { return name_; }

  /// Phase 1: apply commands to the robot (motor targets) for this step.
  virtual void applyCommands(const StepTime&, RobotBody&) {}
  /// Whether sense() casts rays this step, so that moving bodies are refreshed for it first.
  virtual bool castsRays(const StepTime&) const { return false; }
  /// Phase 3: read the stepped world.
  virtual void sense(const StepTime&, const RobotBody&, const RayCaster&) {}
  /// Back to the state at spawn (commands, timers, integrated odometry).
  virtual void reset() {}

 private:
  std::string name_;
};

/// Fires at `rate` [Hz] of sim time (0 = every step), first one period after the start, like Gazebo's
/// plugins.
class UpdateTimer {
 public:
  explicit UpdateTimer(double rate) : period_(rate > 0 ? 1.0 / rate : 0.0) { reset(); }
  /// True when an update is due at `sim_time`; then schedules the next one.
  bool due(const StepTime& time);
  /// Whether due() would be true, without scheduling.
  bool wouldFire(const StepTime& time) const;
  void reset() { next_ = period_; }
  double period() const { return period_; }

 private:
  double period_;
  double next_ = 0;
};

/// Reads a plugin's or sensor's child tags once, at load. Problems go to `diagnostics` naming the plugin and
/// the tag; finish() warns once about each tag that nothing read (Gazebo ignores unknown tags silently).
class PluginTags {
 public:
  PluginTags(const tinyxml2::XMLElement* element, std::string where, Diagnostics& diagnostics);

  bool has(const std::string& tag) const;
  std::string text(const std::string& tag, const std::string& fallback);
  double number(const std::string& tag, double fallback);
  /// A number that must be > 0 (or >= 0 with `allow_zero`).
  double positive(const std::string& tag, double fallback, bool allow_zero = false);
  bool flag(const std::string& tag, bool fallback);
  /// A comma- or space-separated list.
  std::vector<std::string> list(const std::string& tag);
  /// Marks tags as known but not modelled: no warning.
  void accept(std::initializer_list<const char*> tags);
  /// Warns about the tags nothing read.
  void finish();

  Diagnostics& diagnostics() { return diagnostics_; }
  const std::string& where() const { return where_; }

 private:
  const tinyxml2::XMLElement* find(const std::string& tag);

  const tinyxml2::XMLElement* element_;
  std::string where_;
  Diagnostics& diagnostics_;
  std::set<std::string> read_;
};

/// A 64-bit FNV-1a hash: a stable seed for a plugin's noise from its name, the same on every platform.
uint64_t stableHash(const std::string& text);

}  // namespace bullet_sim
