// Plugins: Gazebo plugin and sensor behaviour, ROS-free. Each step runs in three phases: every plugin applies
// its commands, physics steps, then every plugin senses the stepped world, which it may only read (ray
// sensors aim their rays and cast them first, every robot's side by side or behind the next steps' physics:
// castRays).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <random>
#include <set>
#include <string>

#include "bullet_sim/model/model.h"
#include "bullet_sim/plugins/parameter_tree.h"
#include "bullet_sim/model/world.h"
#include "bullet_sim/physics/robot_body.h"
#include "bullet_sim/plugins/image_source.h"
#include "bullet_sim/plugins/ports.h"
#include "bullet_sim/sensing/ray_caster.h"

namespace bullet_sim {

/// The step being simulated: it ends at `sim_time` [s] and lasts `dt` [s]. Nothing in the core reads a clock.
struct StepTime {
  double sim_time = 0;
  double dt = 0;
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
  /// [s] when the update after one due at `time` is due: what due(time) schedules.
  double nextAfter(const StepTime& time) const;
  void reset() { next_ = period_; }
  double period() const { return period_; }

 private:
  double period_;
  double next_ = 0;
};

/// How a plugin's frames take a tf_prefix, as Noetic's gazebo_plugins do (tf::resolve(prefix, frame)); the
/// node reads the prefix from the parameter server, and a frame written with a leading '/' takes none.
enum class TfPrefixRule {
  kSearched,  ///< the tf_prefix parameter searched up from the plugin's namespace (drives, lasers, cameras)
  kNamespaceParam,  ///< <namespace>/tf_prefix only (p3d, range, bumper, block laser)
  kNone,            ///< no prefix (the IMU plugins; ros_control's controllers name their frames in full)
};

/// What a plugin takes from the world at spawn beyond its body and names; a plugin type lists what it needs
/// (PluginType::needs), and only that is set in its PluginSetup.
enum Need : unsigned {
  kNeedGravity = 1 << 0,     ///< the world's gravity (an IMU's reading)
  kNeedOwnRayBody = 1 << 1,  ///< the ray-caster body of the part a sensor sits on, which its rays skip
  kNeedImages = 1 << 2,      ///< the renderer, for cameras
  kNeedGeodesy = 1 << 3,     ///< the world's <spherical_coordinates>, for GPS receivers
  kNeedParameters = 1 << 4,  ///< the parameters read at run time (ros_control's)
};

/// What a plugin is built with at spawn, beside its declaration.
struct PluginSetup {
  // Every plugin's:
  const RobotBody& body;
  std::string robot_name;
  uint64_t seed = 0;  ///< the simulation's; each plugin mixes in its robot's name and its own
  /// spawn_model's -robot_namespace (slashes around it do not count): when given (even "/", the root), it
  /// replaces every plugin's <robotNamespace>, as gazebo_ros's spawn_model does.
  std::optional<std::string> robot_namespace;
  /// Where a plugin reports what it finds wrong while it is built (parameters it reads then); may be nullptr.
  Diagnostics* diagnostics = nullptr;
  TfPrefixRule tf_prefix = TfPrefixRule::kSearched;  ///< its plugin type's

  // Only what the plugin's type needs (Need); the rest keep these values:
  Eigen::Vector3d gravity{0, 0, -9.81};
  BodyId own_ray_body = kNoBody;
  /// Renders the world for cameras; nullptr when the simulation has no renderer (cameras then warn).
  ImageSource* images = nullptr;
  /// The world's <spherical_coordinates>; nullopt when it gives none.
  std::optional<SphericalCoordinates> spherical_coordinates;
  /// The parameters plugins read at run time (ros_control's); nullptr when there are none.
  const ParameterSource* parameters = nullptr;
};

/// What every plugin has: its name and namespace, the head of its messages, an update timer at its config's
/// rate, a noise source seeded from the simulation's seed and its robot's and its own names, and its ports.
class Plugin {
 public:
  Plugin(const PluginDeclaration& declaration, const PluginSetup& setup);
  virtual ~Plugin() = default;
  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;

  const std::string& name() const { return name_; }
  const std::string& robotNamespace() const { return robot_namespace_; }
  /// "plugin [name]" or "sensor [name] on link [link]".
  const std::string& where() const { return where_; }
  const PluginPorts& ports() const { return ports_; }
  /// [Hz] its update timer's rate; 0 = every step.
  double updateRate() const { return timer_.period() > 0 ? 1 / timer_.period() : 0.0; }
  /// [s] when its update after one due at `time` is due.
  double nextUpdateAfter(const StepTime& time) const { return timer_.nextAfter(time); }
  /// Ports that come and go while the plugin runs (a ros_control controller's); none for most plugins.
  virtual std::vector<PortGroup> portGroups() const { return {}; }
  /// Changes whenever portGroups() does.
  virtual uint64_t portGroupsRevision() const { return 0; }
  /// How its frames take a tf_prefix.
  TfPrefixRule tfPrefixRule() const { return tf_prefix_; }
  /// Its frames written with a leading '/': they take no tf_prefix.
  const std::set<std::string>& globalFrames() const { return global_frames_; }

  /// Phase 1: apply commands to the robot (motor targets) for this step.
  virtual void applyCommands(const StepTime&, RobotBody&) {}
  /// Whether sense() reads rays cast this step: moving bodies are refreshed for them, then aimRays() and
  /// castRays() run first.
  virtual bool castsRays(const StepTime&) const { return false; }
  /// Phase 3a, on the stepping thread, when castsRays() said so: takes what this step's rays need from the
  /// stepped body (the sensor's pose) into the plugin's own members, and as little else as it can.
  virtual void aimRays(const StepTime&, const RobotBody&) {}
  /// Phase 3b: casts the aimed rays into the plugin's own buffers, for sense() to publish. Runs on a pool
  /// thread beside other robots' plugins (one robot's plugins on one thread, in their order), or on the
  /// simulation's lane while the next steps' physics runs (SimulationOptions::lockstep false): it may read
  /// the rays and its own members and write only its own buffers, never its noise.
  virtual void castRays(const RayCaster&) {}
  /// Phase 3: read the stepped world. After a cast behind physics, the simulation calls it for the cast's
  /// step once the cast is done, some steps later, when the body has moved on: a plugin whose castsRays()
  /// was true reads what it aimed, not the body.
  virtual void sense(const StepTime&, const RobotBody&, const RayCaster&) {}
  /// Back to the state at spawn: the timer and the noise restart, then onReset().
  void reset();
  /// Its robot's joints were put where they are now from outside the physics (set_model_configuration),
  /// between two steps. Returns warnings for whoever put them there to log.
  virtual std::vector<std::string> jointsPlaced(const RobotBody&) { return {}; }

 protected:
  /// What a plugin resets beyond the timer and the noise (commands, integrated odometry).
  virtual void onReset() {}

  /// For plugins whose namespace defaults to something else than "" (ros_control's: the model's name).
  void setRobotNamespace(std::string robot_namespace) { robot_namespace_ = std::move(robot_namespace); }
  UpdateTimer& timer() { return timer_; }
  const UpdateTimer& timer() const { return timer_; }
  /// The plugin's own seeded noise source.
  std::mt19937_64& noise() { return noise_; }
  /// Three independent samples of N(0, stddev^2); zero, drawing nothing, when `stddev` is 0.
  Eigen::Vector3d gaussian3(double stddev);

  template <class Sample>
  void addOutput(const std::string& topic, const Stream<Sample>& stream, Demand* demand = nullptr) {
    ports_.addOutput(topic, stream, demand);
  }
  template <class Input>
  void addInput(const std::string& topic, InputHandler<Input> handler, Publishers* publishers = nullptr) {
    ports_.addInput(topic, std::move(handler), publishers);
  }
  /// `handler` takes (request, reply), or (request) alone for a request with nothing to reply.
  template <class Request, class Handler>
  void addService(const std::string& name, Handler handler) {
    ports_.addService<Request>(name, std::move(handler));
  }

 private:
  std::string name_;
  std::string robot_namespace_;
  std::string where_;
  TfPrefixRule tf_prefix_;
  std::set<std::string> global_frames_;
  UpdateTimer timer_;
  uint64_t seed_;
  std::mt19937_64 noise_;
  PluginPorts ports_;
};

/// A 64-bit FNV-1a hash: a stable seed for a plugin's noise from its name, the same on every platform.
uint64_t stableHash(const std::string& text);

}  // namespace bullet_sim
