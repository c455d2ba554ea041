// The simulator core's entry point: a world, the robots spawned into it, and the fixed step that runs
// every robot's plugins around the physics. ROS-free; time is a count of steps, never a clock.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/model/convex_decomposition.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/model/world.h"
#include "bullet_sim/physics/physics_world.h"
#include "bullet_sim/physics/robot_body.h"
#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/plugins/registry.h"
#include "bullet_sim/plugins/sensor_interfaces.h"
#include "bullet_sim/sensing/ray_caster.h"

namespace bullet_sim {

/// Where a robot's root link goes: x, y, yaw, and optionally z, roll and pitch. Without z, the robot's lowest
/// collision point rests on the ground (z = 0): no falling from the sky, no sinking.
struct SpawnPose {
  double x = 0, y = 0, yaw = 0;          ///< [m], [m], [rad]
  std::optional<double> z;               ///< [m]
  double roll = 0, pitch = 0;            ///< [rad]
  std::map<std::string, double> joints;  ///< initial joint positions (spawn_model -J) [rad] or [m]; others 0
  /// spawn_model -robot_namespace: when given (even "", the root), it replaces every plugin's
  /// <robotNamespace>.
  std::optional<std::string> robot_namespace;
};

/// A spawn pose from what a service carries: a position [m] and an orientation quaternion. A number that is
/// not finite is an error naming it; a zero quaternion is taken for the identity, with a warning (as Gazebo
/// does); others are normalised. With `place_on_ground`, the position's z is ignored.
SpawnPose spawnPoseFrom(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation,
                        bool place_on_ground, Diagnostics& diagnostics);

class Simulation;
class WorkLane;
class WorkPool;

/// Makes the image source that a simulation's cameras render through; it may keep the simulation to draw.
using ImageSourceFactory = std::function<std::unique_ptr<ImageSource>(const Simulation& simulation)>;

struct SimulationOptions {
  PhysicsOptions physics;
  uint64_t seed = 0;  ///< seeds every sensor's noise; the same inputs and seed give a bit-identical run
  /// Builds the robots' plugins: the registry their models were parsed with. It must outlive the simulation.
  const PluginRegistry* plugins = &PluginRegistry::builtin();
  /// The parameters plugins read at run time (ros_control's): the parameter server in the node, a tree in
  /// tools and tests; nullptr for none. It must outlive the simulation.
  const ParameterSource* parameters = nullptr;
  /// Gives cameras their images (scene/simulation_images.h over a renderer). Without it, cameras publish
  /// nothing: the node always gives one, and tools that draw no camera image need none.
  ImageSourceFactory images;
  /// A spawn pose farther than max_length from the origin is refused.
  Limits limits;
  /// Where the convex parts of moving collision meshes are kept (ConvexDecomposer).
  std::string convex_cache_dir = convexCacheDir();
  /// Threads that share each step's due scans in lockstep and the solve of its simulation islands (bodies
  /// in contact) when there is enough of it, the stepping one included, and the CoACD processes that split a
  /// spawn's meshes side by side; 0: the cores it may run on (taskset, a container's cpuset), at most 4. Any
  /// count gives the same, bit-identical run.
  int threads = 0;
  /// Whether ray sensors cast within the step they measure (Gazebo's --lockstep), or behind the next steps'
  /// physics on a thread of their own: each reading is the same, stamped with its step, and appears at the
  /// end of the first step after its cast is done (in time that depends on the machine), at the latest when
  /// the next cast is due, or when anything moves the ray caster's bodies from outside the step (spawn,
  /// delete, teleport, reset). Physics is the same either way.
  bool lockstep = true;
};

/// One of a robot's outputs whose samples are `Sample`s: the plugin publishing it, its topic and its stream.
template <class Sample>
struct RobotOutput {
  const Plugin* plugin = nullptr;
  std::string topic;  ///< relative to the plugin's namespace
  const Stream<Sample>* stream = nullptr;
};

/// One of a robot's inputs that takes `Input`s (a drive's cmd_vel): the plugin, its topic and its handler.
template <class Input>
struct RobotInput {
  const Plugin* plugin = nullptr;
  std::string topic;
  const InputHandler<Input>* handler = nullptr;
};

/// One of a robot's services that serves `Request`s (a controller manager's): the plugin, its name and its
/// handler.
template <class Request>
struct RobotService {
  const Plugin* plugin = nullptr;
  std::string name;  ///< relative to the plugin's namespace
  const ServiceHandler<Request>* handler = nullptr;
};

/// A spawned robot: its physics and its plugins.
class Robot {
 public:
  Robot(std::string name, std::unique_ptr<PhysicsRobot> body, const Eigen::Isometry3d& spawn_pose);
  ~Robot();

  const std::string& name() const { return name_; }
  PhysicsRobot& body() { return *body_; }
  const PhysicsRobot& body() const { return *body_; }
  const std::vector<std::unique_ptr<Plugin>>& plugins() const { return plugins_; }

  /// Every output of its plugins whose samples are `Sample`s (LaserScan, CameraImage, ...), the ports that
  /// come and go (a controller's) included, in plugin order: what scenes, checks and tools read.
  template <class Sample>
  std::vector<RobotOutput<Sample>> outputs() const {
    std::vector<RobotOutput<Sample>> found;
    forEachPorts([&](const Plugin& plugin, const PluginPorts& ports) {
      for (const OutputPort& port : ports.outputs) {
        if (auto* stream = std::get_if<const Stream<Sample>*>(&port.stream))
          found.push_back({&plugin, port.topic, *stream});
      }
    });
    return found;
  }
  /// Its plugins that are `Interface`s (sensor_interfaces.h: RaySensor, CameraSensor), in plugin order.
  template <class Interface>
  std::vector<std::pair<const Plugin*, const Interface*>> sensors() const {
    std::vector<std::pair<const Plugin*, const Interface*>> found;
    for (const auto& plugin : plugins_) {
      if (const auto* typed = dynamic_cast<const Interface*>(plugin.get()))
        found.emplace_back(plugin.get(), typed);
    }
    return found;
  }
  /// Its wheel-ground model: "raycast" or "contact".
  const std::string& wheelModel() const { return wheel_model_; }
  /// Every input of its plugins that takes `Input`s (Twist, ...), in plugin order.
  template <class Input>
  std::vector<RobotInput<Input>> inputs() const {
    std::vector<RobotInput<Input>> found;
    forEachPorts([&](const Plugin& plugin, const PluginPorts& ports) {
      for (const InputPort& port : ports.inputs) {
        if (auto* handler = std::get_if<InputHandler<Input>>(&port.sink))
          found.push_back({&plugin, port.topic, handler});
      }
    });
    return found;
  }
  /// Every service of its plugins that serves `Request`s, in plugin order.
  template <class Request>
  std::vector<RobotService<Request>> services() const {
    std::vector<RobotService<Request>> found;
    forEachPorts([&](const Plugin& plugin, const PluginPorts& ports) {
      for (const ServicePort& port : ports.services) {
        if (auto* handler = std::get_if<ServiceHandler<Request>>(&port.handler))
          found.push_back({&plugin, port.name, handler});
      }
    });
    return found;
  }

 private:
  friend class Simulation;
  /// Calls `visit(plugin, ports)` for each plugin's own ports, then for each of its port groups.
  template <class Visit>
  void forEachPorts(Visit visit) const {
    for (const auto& plugin : plugins_) {
      visit(*plugin, plugin->ports());
      for (const PortGroup& group : plugin->portGroups()) visit(*plugin, *group.ports);
    }
  }
  /// Whether plugin k's rays are being cast (behind physics, or in this step's castRays).
  bool casting(size_t k) const { return !casting_.empty() && casting_[k]; }

  std::string name_;
  std::unique_ptr<PhysicsRobot> body_;
  Eigen::Isometry3d spawn_pose_;
  JointPositions spawn_joints_;
  std::vector<std::unique_ptr<Plugin>> plugins_;
  /// Per plugin, whether its rays are being cast behind physics (empty when none is): it senses once they
  /// are.
  std::vector<bool> casting_;
  std::vector<BodyId> ray_bodies_;  ///< per part; kNoBody for a part without collisions
  std::string wheel_model_;
};

/// Work that a part outside the simulation (the world API's scheduled wrenches and efforts) has done at every
/// step. It hooks itself into the simulation for its lifetime, which the simulation must outlast.
class StepHooks {
 public:
  StepHooks(const StepHooks&) = delete;
  StepHooks& operator=(const StepHooks&) = delete;
  /// At the start of each step, before the plugins apply their commands; time() is the step's start.
  virtual void beforeStep() = 0;
  /// After robot `name` was removed.
  virtual void robotRemoved(const std::string& name) = 0;

 protected:
  explicit StepHooks(Simulation& simulation);
  virtual ~StepHooks();

 private:
  Simulation& hooked_;
};

class Simulation {
 public:
  explicit Simulation(WorldSpec world, SimulationOptions options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Adds a robot named `name`. Throws SpecError listing every problem (a name in use, a pose that is not
  /// finite or beyond the limits, a plugin naming a missing joint, ...), and then leaves the simulation as it
  /// was. Load messages go to `warnings`.
  /// A world saved with the robot in it is refused: a world model of the robot's name, or one with exactly
  /// the robot's collision shapes (matched one to one by type and size) whose bounding box overlaps the
  /// robot's at the spawn pose.
  Robot& spawn(const std::string& name, ModelSpec model, const SpawnPose& pose,
               std::vector<std::string>* warnings = nullptr);
  /// False when there is no robot of that name.
  bool remove(const std::string& name);
  Robot* robot(const std::string& name);
  const Robot* robot(const std::string& name) const;
  std::vector<std::string> robotNames() const;

  /// One step: plugins apply commands, physics advances by the step size (in substeps, where a robot's
  /// stiffest spring or lightest link needs shorter ones), then plugins sense.
  void step();
  /// One line on the physics substep robot `name` runs at, and what sets it. Throws std::invalid_argument
  /// for an unknown robot.
  std::string substepNote(const std::string& name) const;
  /// Physics substeps so far whose simulation islands (bodies in contact) were solved side by side on the
  /// pool's threads (PhysicsWorld::shareSolvesWith).
  uint64_t sharedSolves() const { return physics_->sharedSolves(); }
  int physicsSubsteps() const { return physics_->substeps(); }  ///< per step, as its robots need
  /// Robots back at their spawn poses and plugins as at spawn; time goes on.
  void resetWorld();
  /// resetWorld, and time restarts: the next step ends at t = step size.
  void resetSimulation();

  double time() const { return timeAfter(steps_); }  ///< [s]
  uint64_t steps() const { return steps_; }
  double stepSize() const { return options_.physics.step_size; }  ///< [s]
  /// [s] from the next step on; sim time goes on from where it is. Throws std::invalid_argument unless
  /// positive and finite.
  void setStepSize(double step_size);
  /// Gravity and the Bullet world.
  PhysicsWorld& physics() { return *physics_; }
  const WorldSpec& world() const { return world_; }
  const Limits& limits() const { return options_.limits; }

  /// Where each of the world's models is now (parallel to world().models).
  Eigen::Isometry3d worldModelPose(size_t model) const;
  /// The frame in which visual `visual` of world model `model` has its origin now: the model's frame, or,
  /// for a visual on a link that turned on a joint, that frame moved with the link. Its pose is this frame *
  /// its origin.
  Eigen::Isometry3d worldVisualFrame(size_t model, size_t visual) const;
  /// Moves static world model `model`, with its collisions, to `pose`.
  void moveWorldModel(size_t model, const Eigen::Isometry3d& pose);
  /// The rigid body of non-static world model `model`, a robot without plugins; nullptr for a static one.
  Robot* worldBody(size_t model);
  /// After bodies moved between steps (a teleport, joints set), the ray caster (sensors, raycast wheels)
  /// sees them where they are now.
  void refreshRays();
  /// Delivers the readings of rays cast behind physics (lockstep false) now: waits for their cast, then their
  /// plugins sense for the step they were aimed at. Nothing to do in lockstep.
  void finishCasts();

 private:
  friend class StepHooks;
  /// A world model as it is now: where, and its ray-caster body; or, for a non-static one, its rigid body,
  /// which the world API treats as a robot without plugins.
  struct PlacedWorldModel {
    Eigen::Isometry3d pose;
    BodyId ray_body = kNoBody;
    std::unique_ptr<Robot> body;
    /// A body's: per link of its WorldModelSpec, its pose in the file, inverted, times the model's there
    /// (what makes the link's pose now the frame of its visuals' origins); per visual, its link.
    std::vector<Eigen::Isometry3d> link_to_model;
    std::vector<size_t> visual_link;
  };
  double timeAfter(uint64_t steps) const {
    return time_base_ + static_cast<double>(steps - steps_at_base_) * options_.physics.step_size;
  }
  /// Cuts the step into substeps no longer than any moving model's SubstepLimit, and tells them.
  void fitSubsteps();
  /// The non-static world model `model` as a body at its pose in the file, into `placed`.
  void makeWorldBody(const WorldModelSpec& model, PlacedWorldModel& placed);
  /// The robots and the world's bodies: what steps.
  std::vector<Robot*> movingModels();
  /// Adds the parts of a robot or of a world's body to the ray caster (not yet committed).
  void addRayBodies(Robot& robot);
  /// Adds the robot's parts to the ray caster and builds its plugins; on an error, takes the parts back out.
  void equip(Robot& robot, const std::optional<std::string>& robot_namespace, Diagnostics& diagnostics);
  /// Phase 3a: the ray plugins due this step aim their rays, and are marked as casting. Returns when the
  /// first of them is due again.
  double aimRays(const StepTime& time);
  /// Phases 3a and 3b: the ray plugins due this step aim their rays; the ray caster's moving bodies are moved
  /// where they are now, and the rays cast, each robot's on one of the pool's threads, or all on the lane
  /// (not in lockstep).
  void castRays(const StepTime& time);
  /// The rays of `robot`'s plugins marked as casting.
  static void castEach(const Robot& robot, RayCaster& rays);
  /// The ray plugins due this step aim, and their rays are queued on the lane behind the casts before.
  void castBehind(const StepTime& time);
  /// Delivers the readings of the first `count` casts behind physics: waits for them, then their plugins
  /// sense.
  void deliverCasts(size_t count);
  /// How many casts at the front the lane has finished.
  size_t finishedCasts() const;
  /// Delivers the casts up to the last one with a plugin due again at `time`, so that it senses before it
  /// aims.
  void deliverCastsDue(const StepTime& time);
  /// Where every moving model's ray-caster bodies are now, into `poses`.
  void rayBodyPoses(std::vector<std::pair<BodyId, Eigen::Isometry3d>>& poses);
  /// Moves the ray caster's bodies to `poses`, and commits.
  void moveRayBodies(const std::vector<std::pair<BodyId, Eigen::Isometry3d>>& poses);
  /// Phase 3: every plugin senses, but those whose rays are still being cast.
  void sense(const StepTime& time);

  WorldSpec world_;
  SimulationOptions options_;
  /// Casts each step's rays in lockstep and shares physics_' solve of its islands: outlives physics_.
  std::unique_ptr<WorkPool> pool_;
  std::unique_ptr<PhysicsWorld> physics_;
  RayCaster rays_;
  ConvexDecomposer decomposer_{options_.convex_cache_dir, options_.threads};
  std::unique_ptr<ImageSource> images_;         ///< outlives the robots' cameras
  std::vector<std::unique_ptr<Robot>> robots_;  ///< destroyed before physics_, which they live in
  std::vector<PlacedWorldModel> world_models_;  ///< parallel to world_.models; destroyed before physics_
  std::vector<StepHooks*> hooks_;  ///< in the order they hooked in
  std::vector<Robot*> ray_casting_;  ///< this step's robots with a ray plugin due, in robot order
  /// The rays of one step's robots, cast on the lane.
  struct CastBehind {
    std::vector<Robot*> robots;  ///< in robot order
    StepTime time;               ///< the step they were aimed at
    double next_due;             ///< [s] when the first of them is due again, so delivered by then
    uint64_t ticket;             ///< the lane's job
  };
  std::deque<CastBehind> casts_behind_;  ///< in the order they were started, each robot in one at most
  std::vector<std::pair<BodyId, Eigen::Isometry3d>> ray_poses_;  ///< where the ray caster's bodies go next
  bool delivered_since_step_ = false;   ///< scans were delivered since the last step ended
  std::unique_ptr<WorkLane> lane_;      ///< casts behind physics when not in lockstep; stops first
  uint64_t steps_ = 0;
  double time_base_ = 0;        ///< [s] at steps_at_base_: the step size may change
  uint64_t steps_at_base_ = 0;
};

}  // namespace bullet_sim
