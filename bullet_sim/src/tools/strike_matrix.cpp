#include "bullet_sim/tools/strike_matrix.h"

#include <tinyxml2.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>

#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/assets/package_resolver.h"
#include "bullet_sim/plugins/parameter_tree.h"
#include "bullet_sim/plugins/registry.h"
#include "bullet_sim/simulation/world_api.h"
#include "bullet_sim/tools/urdf_edits.h"

namespace bullet_sim {

namespace {

constexpr double kWallThickness = 0.1;   ///< [m]
constexpr double kPanelThickness = 0.02;  ///< [m]
constexpr double kTargetLength = 6.0;    ///< [m] of a wall or panel, across the robot's path
constexpr double kPostWidth = 0.4;       ///< [m] of a door frame's post, across the path
constexpr double kTargetHeight = 2.5;    ///< [m]
constexpr double kSettleTime = 0.3;      ///< [s] at rest after the spawn
constexpr double kGivenGap = 0.5;        ///< [m] before the target where a slow robot is given its speed
constexpr double kCoastGap = 0.3;        ///< [m] before the target where a coasting robot is given it
constexpr double kReachedFraction = 0.95;  ///< of the commanded speed: reached
constexpr double kAfterContact = 1.0;    ///< [s] the command runs after the first contact
constexpr double kWatchAfter = 0.5;      ///< [s] watched after the command ends
constexpr double kPictureAfter = 0.3;    ///< [s] after the first contact: the snapshot of the strike
constexpr double kSamplePeriod = 0.05;   ///< [s] between path samples
constexpr double kPointSpacing = 0.01;   ///< [m] between the sampled points of a small surface
constexpr int kMostDivisions = 12;       ///< of a large surface's edge
/// [m] points this much behind the first to meet the target meet it too
constexpr double kFirstTouch = 0.002;
constexpr double kSupportBand = 0.001;   ///< [m] points this close to the lowest one rest on the ground
constexpr double kMotorsOffTorque = 1e-9;  ///< [N m] the plugins refuse 0
constexpr double kGravity = 9.81;        ///< [m/s^2]
constexpr double kWallFriction = 1.0;    ///< mu of the targets (Gazebo's default)
constexpr double kRoomStep = 0.01;       ///< [rad] between the attitudes roomToTip tries
constexpr double kRoomTolerance = 0.01;  ///< [m] into the target or the ground that roomToTip lets pass
constexpr double kRearDrivenTolerance = 0.01;  ///< [m] driven wheels this close to the rear edge are on it
// The rules (issue 28).
constexpr double kSlowTilt = 0.1;    ///< [rad] upright at up to kSlowSpeed
constexpr double kFastTilt = 0.35;   ///< [rad] upright above it
constexpr double kSlowSpeed = 0.5;   ///< [m/s]
constexpr double kMaxRise = 0.05;    ///< [m] no leap
constexpr double kClimbed = 0.01;    ///< [m] of the root's rise that shows a climb
constexpr double kFlingSlack = 0.05;  ///< [m] beyond the command's path
constexpr double kCorrectingSpeed = 0.1;  ///< [m/s] the depenetration cap: energy allowance 1/2 M v^2
constexpr double kEnergyFraction = 0.01;  ///< and 1 % of the start

/// A point on the surface of a robot's collision, in its part's frame.
struct SurfacePoint {
  Eigen::Vector3d position;
  int part;
  bool driven;  ///< on a wheel the drive turns
};

/// How many parts to cut `length` [m] into: kPointSpacing apart, between `fewest` and `most`.
int divisions(double length, int fewest, int most) {
  return std::clamp(static_cast<int>(std::ceil(length / kPointSpacing)), fewest, most);
}

void addGrid(const Eigen::Vector3d& corner, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
             std::vector<Eigen::Vector3d>& points) {
  const int na = divisions(a.norm(), 1, kMostDivisions), nb = divisions(b.norm(), 1, kMostDivisions);
  for (int i = 0; i <= na; ++i) {
    for (int j = 0; j <= nb; ++j) points.push_back(corner + a * i / na + b * j / nb);
  }
}

/// Points on a shape's surface, in its collision frame: kPointSpacing apart on small shapes, at most
/// kMostDivisions along an edge of large ones (a box's faces), a cylinder's caps as rings.
std::vector<Eigen::Vector3d> surfacePoints(const Shape& shape) {
  std::vector<Eigen::Vector3d> points;
  switch (shape.type) {
    case Shape::Type::kBox: {
      const Eigen::Vector3d e = shape.box_size / 2;
      for (int axis = 0; axis < 3; ++axis) {
        const Eigen::Vector3d u = Eigen::Vector3d::Unit((axis + 1) % 3) * 2 * e[(axis + 1) % 3];
        const Eigen::Vector3d v = Eigen::Vector3d::Unit((axis + 2) % 3) * 2 * e[(axis + 2) % 3];
        for (double side : {-1.0, 1.0}) {
          Eigen::Vector3d corner = -e;
          corner[axis] = side * e[axis];
          addGrid(corner, u, v, points);
        }
      }
      break;
    }
    case Shape::Type::kCylinder: {
      const double r = shape.radius, half = shape.length / 2;
      const int around = divisions(2 * M_PI * r, 16, 2 * kMostDivisions);
      const int along = divisions(shape.length, 1, kMostDivisions);
      for (int k = 0; k < around; ++k) {
        const double angle = 2 * M_PI * k / around;
        const Eigen::Vector2d rim = r * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        for (int i = 0; i <= along; ++i)
          points.emplace_back(rim.x(), rim.y(), -half + shape.length * i / along);
        for (double z : {-half, half}) points.emplace_back(rim.x() / 2, rim.y() / 2, z);
      }
      break;
    }
    case Shape::Type::kSphere: {
      const int count = std::clamp(
          static_cast<int>(4 * M_PI * shape.radius * shape.radius / (kPointSpacing * kPointSpacing)),
          64, 4 * kMostDivisions * kMostDivisions);
      const double golden = M_PI * (3 - std::sqrt(5.0));
      for (int i = 0; i < count; ++i) {  // a Fibonacci sphere
        const double z = 1 - 2 * (i + 0.5) / count, ring = std::sqrt(1 - z * z);
        points.push_back(shape.radius *
                         Eigen::Vector3d(ring * std::cos(golden * i), ring * std::sin(golden * i), z));
      }
      break;
    }
    case Shape::Type::kMesh:
      if (shape.mesh) points = shape.mesh->vertices;
      break;
    case Shape::Type::kPlane:
      break;
  }
  return points;
}

/// How the matrix drives the robot, whatever drives it.
struct Drive {
  std::vector<std::string> joints;  ///< the driven wheels'
  double torque = 0;                ///< [N m] per driven wheel
  double radius = 0;                ///< [m] of the driven wheels
  double acceleration = 0;          ///< [m/s^2] the drive's ramp; 0 = none
  double max_speed = std::numeric_limits<double>::infinity();  ///< [m/s] the drive's cap
  std::function<void(double speed, double sim_time)> command;
};

double effortLimit(const ModelSpec& model, const std::string& joint) {
  const JointSpec* spec = model.joint(joint);
  return spec && std::isfinite(spec->effort) ? spec->effort : 0.0;
}

double wheelRadiusOf(const ModelSpec& model, const std::string& joint) {
  const JointSpec* spec = model.joint(joint);
  const LinkSpec* link = spec ? model.link(spec->child) : nullptr;
  return link && !link->collisions.empty() ? link->collisions.front().shape.radius : 0.0;
}

/// A command of `speed` along x through `input`, a cmd_vel.
std::function<void(double speed, double sim_time)> forwardCommand(const InputHandler<Twist>& input) {
  return [&input](double speed, double sim_time) {
    Twist twist;
    twist.linear.x() = speed;
    input(twist, sim_time);
  };
}

/// Calls `robot`'s service that serves `Request`s (its controller manager's), throwing what it refuses.
template <class Request>
void callService(const Robot& robot, const Request& request, const std::string& what) {
  typename Request::Reply reply;
  const std::string problem = (*robot.services<Request>().front().handler)(request, reply);
  if (!problem.empty()) throw std::runtime_error(what + ": " + problem);
}

/// The robot's ros_control diff drive, once every controller in `parameters` is loaded and started through
/// the controller manager's services: the controller's wheels, limits and cmd_vel.
std::optional<Drive> rosControlDrive(const Robot& robot, const ParameterTree& parameters) {
  if (robot.services<LoadControllerRequest>().empty()) return std::nullopt;
  SwitchControllerRequest start;
  start.strictness = SwitchControllerRequest::kStrict;
  for (const auto& name : parameters.keys()) {
    if (!parameters.has(name + "/type")) continue;
    callService(robot, LoadControllerRequest{name}, "controller [" + name + "]");
    start.start.push_back(name);
  }
  callService(robot, start, "starting the controllers");
  for (const auto& name : start.start) {
    const ParameterTree config = parameters.at(name);
    if (config.text("type", "") != "diff_drive_controller/DiffDriveController") continue;
    Drive drive;
    drive.joints = config.texts("left_wheel");
    for (const auto& joint : config.texts("right_wheel")) drive.joints.push_back(joint);
    const ModelSpec& model = robot.body().spec();
    drive.torque = effortLimit(model, drive.joints.front());
    drive.radius = wheelRadiusOf(model, drive.joints.front());
    if (config.flag("linear/x/has_acceleration_limits", false))
      drive.acceleration = config.number("linear/x/max_acceleration", 0);
    if (config.flag("linear/x/has_velocity_limits", false))
      drive.max_speed = config.number("linear/x/max_velocity", drive.max_speed);
    for (const auto& input : robot.inputs<Twist>()) {
      if (input.topic == name + "/cmd_vel") drive.command = forwardCommand(*input.handler);
    }
    if (!drive.command) throw std::logic_error("controller [" + name + "] takes no cmd_vel");
    return drive;
  }
  throw std::runtime_error("no diff_drive_controller/DiffDriveController among the controllers");
}

/// The robot's drive plugin, by what its plugin type says of its traction, commanded through its cmd_vel.
Drive pluginDrive(const Robot& robot) {
  const PluginRegistry& registry = PluginRegistry::builtin();
  for (const PluginDeclaration& declaration : robot.body().spec().plugins) {
    const PluginType* type = registry.typeOf(declaration);
    if (!type || !type->driven) continue;
    const std::optional<Traction> traction = type->driven(declaration).traction;
    if (!traction) continue;
    Drive drive{traction->wheels, traction->torque, traction->wheel_radius, traction->acceleration,
                traction->max_speed, nullptr};
    for (const auto& input : robot.inputs<Twist>()) {
      if (input.plugin->name() == declaration.name) drive.command = forwardCommand(*input.handler);
    }
    if (!drive.command) throw std::logic_error(declaration.where() + " takes no cmd_vel");
    return drive;
  }
  throw std::runtime_error(
      "the robot has no drive plugin with wheels of its own, nor ros_control, to drive it");
}

Drive driveOf(const Robot& robot, const ParameterTree& parameters) {
  if (auto drive = rosControlDrive(robot, parameters)) return *drive;
  return pluginDrive(robot);
}

/// The robot's collision surfaces, sampled, in its parts' frames.
std::vector<SurfacePoint> samplePoints(const RobotBody& body, const Drive& drive) {
  std::vector<std::string> driven_links;
  for (const auto& joint : drive.joints) driven_links.push_back(body.spec().joint(joint)->child);
  std::vector<SurfacePoint> points;
  const auto& parts = body.parts();
  for (size_t k = 0; k < parts.size(); ++k) {
    for (size_t c = 0; c < parts[k].collisions.size(); ++c) {
      const Collision& collision = parts[k].collisions[c];
      const bool driven = std::find(driven_links.begin(), driven_links.end(), parts[k].sources[c].link) !=
                          driven_links.end();
      for (const auto& point : surfacePoints(collision.shape))
        points.push_back({collision.origin * point, static_cast<int>(k), driven});
    }
  }
  return points;
}

std::vector<Eigen::Vector3d> worldPoints(const RobotBody& body, const std::vector<SurfacePoint>& points) {
  std::vector<Eigen::Isometry3d> poses;
  for (size_t k = 0; k < body.parts().size(); ++k) poses.push_back(body.partPose(static_cast<int>(k)));
  std::vector<Eigen::Vector3d> world;
  world.reserve(points.size());
  for (const auto& point : points) world.push_back(poses[point.part] * point.position);
  return world;
}

/// A target as a box: its pose (x along its thickness, towards the far side) and half extents.
struct TargetBox {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d half = Eigen::Vector3d::Zero();

  Eigen::Vector3d normal() const { return pose.linear().col(0); }  ///< into the target
  /// How far `point` travels along `direction` to meet the box; +infinity when it never does.
  double distanceAlong(const Eigen::Vector3d& point, const Eigen::Vector3d& direction) const {
    const Eigen::Vector3d p = pose.inverse() * point, d = pose.linear().transpose() * direction;
    double enter = 0, leave = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(d[axis]) < 1e-12) {
        if (std::abs(p[axis]) > half[axis]) return std::numeric_limits<double>::infinity();
        continue;
      }
      double a = (-half[axis] - p[axis]) / d[axis], b = (half[axis] - p[axis]) / d[axis];
      if (a > b) std::swap(a, b);
      enter = std::max(enter, a);
      leave = std::min(leave, b);
    }
    return enter <= leave ? enter : std::numeric_limits<double>::infinity();
  }
  /// [m] from `point` to the box (0 inside).
  double distance(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d p = (pose.inverse() * point).cwiseAbs() - half;
    return p.cwiseMax(0.0).norm();
  }
  /// How deep `point` is inside the box (<= 0 outside).
  double depth(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d p = (pose.inverse() * point).cwiseAbs();
    return (half - p).minCoeff();
  }
  /// Whether `point` lies more than `margin` [m] past the near face, within the box's extent across.
  bool pastNearFace(const Eigen::Vector3d& point, double margin) const {
    const Eigen::Vector3d p = pose.inverse() * point;
    return p.x() > -half.x() + margin && std::abs(p.y()) < half.y() && std::abs(p.z()) < half.z();
  }
  /// Which side of the box `point` is on, straight across its thickness: -1 before the near face, +1 past the
  /// far face, 0 inside or off to a side (within a margin of its edges, which a robot sliding past may
  /// graze).
  int side(const Eigen::Vector3d& point) const {
    constexpr double kGraze = 0.01;  // [m]
    const Eigen::Vector3d p = pose.inverse() * point;
    if (std::abs(p.y()) > half.y() - kGraze || std::abs(p.z()) > half.z() - kGraze) return 0;
    return p.x() < -half.x() ? -1 : p.x() > half.x() ? 1 : 0;
  }
};

/// The target of `cell` (its size; parked far away).
TargetBox targetShape(const StrikeCell& cell) {
  TargetBox box;
  const bool post = cell.target == StrikeTarget::kDoorEdge;
  const double thickness = cell.target == StrikeTarget::kPanel ? kPanelThickness : kWallThickness;
  box.half = Eigen::Vector3d(thickness, post ? kPostWidth : kTargetLength, kTargetHeight) / 2;
  box.pose.translation() = Eigen::Vector3d(1000, 1000, box.half.z());
  return box;
}

/// The target of `cell`, turned by its angle from `heading` and placed so that the robot's first point to
/// meet it travels `gap` along `heading`. A wall or panel spans the robot's path; a door frame's post has its
/// near vertical edge a quarter of the robot's width in from the robot's left side, and reaches further left.
TargetBox placeTarget(const StrikeCell& cell, const std::vector<Eigen::Vector3d>& points,
                      const Eigen::Vector3d& heading, double gap) {
  TargetBox box = targetShape(cell);
  const double yaw = std::atan2(heading.y(), heading.x()) + cell.angle;
  box.pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(heading);
  double low = std::numeric_limits<double>::infinity(), high = -low, ahead = -low;
  for (const auto& p : points) {
    low = std::min(low, p.dot(left));
    high = std::max(high, p.dot(left));
    ahead = std::max(ahead, p.dot(heading));
  }
  const bool post = cell.target == StrikeTarget::kDoorEdge;
  // A point on the robot's path: the post's near edge, or the wall's middle.
  const Eigen::Vector3d on_path =
      (post ? high - (high - low) / 4 : (low + high) / 2) * left + (ahead + 1) * heading;
  const Eigen::Vector3d from_centre(-box.half.x(), post ? -box.half.y() : 0.0, 0.0);
  box.pose.translation() =
      on_path - box.pose.linear() * from_centre + box.half.z() * Eigen::Vector3d::UnitZ();
  double first = std::numeric_limits<double>::infinity();
  for (const auto& p : points) first = std::min(first, box.distanceAlong(p, heading));
  box.pose.translation() += (gap - first) * heading;
  return box;
}

WorldModelSpec targetModel(const TargetBox& box) {
  Shape shape;
  shape.type = Shape::Type::kBox;
  shape.box_size = 2 * box.half;
  WorldModelSpec model;
  model.name = "strike_target";
  model.is_static = true;
  model.pose = box.pose;
  model.collisions.push_back({Eigen::Isometry3d::Identity(), shape, "strike_target::link::collision"});
  model.visuals.push_back({Eigen::Isometry3d::Identity(), shape, Eigen::Vector4d(0.8, 0.8, 0.75, 1), ""});
  return model;
}

}  // namespace

std::string targetName(StrikeTarget target) {
  switch (target) {
    case StrikeTarget::kWall: return "wall";
    case StrikeTarget::kDoorEdge: return "door_edge";
    case StrikeTarget::kPanel: return "panel";
  }
  return "?";
}

std::string cellName(const StrikeRobot& robot, const StrikeCell& cell) {
  std::ostringstream name;
  name << robot.name << " " << cell.wheel_model << " " << cell.step * 1000 << "ms " << cell.speed << "m/s "
       << std::lround(cell.angle * 180 / M_PI) << "deg " << targetName(cell.target)
       << (cell.coast ? " coast" : "");
  return name.str();
}

double robotMass(const ModelSpec& model) {
  double mass = 0;
  for (const auto& link : model.links) mass += link.inertial ? link.inertial->mass : 0.0;
  return mass;
}

double robotEnergy(const Robot& robot, const Eigen::Vector3d& gravity) {
  const PhysicsRobot& body = robot.body();
  double energy = body.elasticEnergy();
  for (const auto& link : body.spec().links) {
    if (!link.inertial || link.inertial->mass <= 0) continue;
    const Eigen::Isometry3d pose = body.linkPose(link.name);
    const Eigen::Vector3d omega = body.linkAngularVelocity(link.name);
    const Eigen::Vector3d com = pose * link.inertial->com;
    const Eigen::Vector3d velocity =
        body.linkLinearVelocity(link.name) + omega.cross(com - pose.translation());
    const Eigen::Matrix3d inertia = pose.linear() * link.inertial->inertia * pose.linear().transpose();
    const double mass = link.inertial->mass;
    energy +=
        0.5 * mass * velocity.squaredNorm() + 0.5 * omega.dot(inertia * omega) - mass * gravity.dot(com);
  }
  return energy;
}

std::string withStrikeWheelModel(const std::string& urdf, const std::string& wheel_model) {
  return withPluginTag(urdf,
                       {"libgazebo_ros_diff_drive.so", "libgazebo_ros_skid_steer_drive.so",
                        "libgazebo_ros_ackermann_drive.so", "libgazebo_ros_control.so"},
                       [](const std::string&) { return "wheelModel"; }, wheel_model);
}

namespace {

/// The joints of the wheels that drive the robot: each drive plugin's traction, as its plugin type says, and
/// the left and right wheels of each diff_drive_controller in `controllers`.
std::vector<std::string> tractionWheels(const ModelSpec& model, const ParameterTree& controllers) {
  std::vector<std::string> wheels;
  const PluginRegistry& registry = PluginRegistry::builtin();
  for (const PluginDeclaration& declaration : model.plugins) {
    const PluginType* type = registry.typeOf(declaration);
    if (!type || !type->driven) continue;
    const std::optional<Traction> traction = type->driven(declaration).traction;
    if (traction) wheels.insert(wheels.end(), traction->wheels.begin(), traction->wheels.end());
  }
  for (const auto& name : controllers.keys()) {
    if (!controllers.has(name + "/type")) continue;
    const ParameterTree config = controllers.at(name);
    if (config.text("type", "") != "diff_drive_controller/DiffDriveController") continue;
    for (const char* side : {"left_wheel", "right_wheel"}) {
      for (const auto& joint : config.texts(side)) wheels.push_back(joint);
    }
  }
  return wheels;
}

}  // namespace

std::string withMotorsOff(const std::string& urdf, const std::string& control_yaml) {
  std::vector<std::string> warnings;  // parseModel of the edited URDF reports them
  const ModelSpec model = parseModel(urdf, "motors off", PackageResolver::fromEnvironment(), &warnings);
  const ParameterTree controllers =
      control_yaml.empty() ? ParameterTree() : ParameterTree::fromYaml(control_yaml, "motors off");
  std::ostringstream torque;
  torque << kMotorsOffTorque;
  return withPluginTag(
      withEffortLimit(urdf, tractionWheels(model, controllers), kMotorsOffTorque),
      {"libgazebo_ros_diff_drive.so", "libgazebo_ros_skid_steer_drive.so"},
      [](const std::string& filename) {
        return filename == "libgazebo_ros_diff_drive.so" ? "wheelTorque" : "torque";
      },
      torque.str());
}

namespace {

/// The robot settled on the ground, as the bounds see it.
struct Settled {
  Eigen::Isometry3d root = Eigen::Isometry3d::Identity();
  Eigen::Vector3d heading = Eigen::Vector3d::UnitX();  ///< its root's x, level
  std::vector<Eigen::Vector3d> points;                 ///< world, parallel to the sampled points
  double ground = 0;                                   ///< [m] its lowest point's height
  MassProperties mass;                                 ///< world frame
  double friction = 1;                                 ///< of its driven wheels
};

Settled settledState(const Robot& robot, const std::vector<SurfacePoint>& points, const Drive& drive) {
  const PhysicsRobot& body = robot.body();
  const ModelSpec& model = body.spec();
  Settled settled;
  settled.root = body.linkPose(model.root);
  settled.heading = Eigen::Vector3d(settled.root.linear()(0, 0), settled.root.linear()(1, 0), 0).normalized();
  settled.points = worldPoints(body, points);
  settled.ground = std::numeric_limits<double>::infinity();
  for (const auto& p : settled.points) settled.ground = std::min(settled.ground, p.z());
  std::vector<std::pair<std::string, Eigen::Isometry3d>> placed;
  for (const auto& link : model.links) placed.emplace_back(link.name, body.linkPose(link.name));
  settled.mass = combineInertia(model, placed);
  const LinkSpec* wheel = model.link(model.joint(drive.joints.front())->child);
  settled.friction = wheel ? wheel->surface.mu1 : 1.0;
  return settled;
}

/// Where the robot rests on the ground: per part that touches it, where along n and whether it is driven.
struct Supports {
  struct Part {
    int part;
    double along = 0;  ///< [m] from the centre of mass along n, its ground points' mean
    bool driven = false;
    double load = 0;  ///< [N] by the lever rule between the front and the rear groups
  };
  std::vector<Part> parts;
  double front = 0, rear = 0;  ///< [m] the support edges' distances from the centre of mass along n

  const Part* find(int part) const {
    for (const auto& p : parts) {
      if (p.part == part) return &p;
    }
    return nullptr;
  }
};

Supports supportsOf(const Settled& settled, const std::vector<SurfacePoint>& points,
                    const Eigen::Vector3d& n) {
  Supports supports;
  std::vector<int> counts;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = settled.points[i];
    if (p.z() > settled.ground + kSupportBand) continue;
    const double along = (p - settled.mass.com).dot(n);
    supports.front = std::max(supports.front, along);
    supports.rear = std::max(supports.rear, -along);
    auto found = std::find_if(supports.parts.begin(), supports.parts.end(),
                              [&](const Supports::Part& part) { return part.part == points[i].part; });
    if (found == supports.parts.end()) {
      supports.parts.push_back({points[i].part, 0, points[i].driven, 0});
      counts.push_back(0);
      found = supports.parts.end() - 1;
    }
    found->along += along;
    ++counts[found - supports.parts.begin()];
  }
  // The lever rule between the mean front and rear support lines, each group's share split evenly.
  double front_sum = 0, rear_sum = 0;
  int fronts = 0, rears = 0;
  for (size_t k = 0; k < supports.parts.size(); ++k) {
    Supports::Part& part = supports.parts[k];
    part.along /= counts[k];
    (part.along > 0 ? front_sum : rear_sum) += part.along;
    ++(part.along > 0 ? fronts : rears);
  }
  const double weight = settled.mass.mass * kGravity;
  const double front = fronts ? front_sum / fronts : 0, rear = rears ? -rear_sum / rears : 0;
  for (auto& part : supports.parts) {
    const bool ahead = part.along > 0;
    if (!fronts || !rears) part.load = weight / supports.parts.size();
    else part.load = weight * (ahead ? rear : front) / (front + rear) / (ahead ? fronts : rears);
  }
  return supports;
}

/// Whether the robot, held at the target by its struck point, can turn about a support edge (`backwards`:
/// the rear one, its top going back) far enough to carry its centre of mass over it, before another of its
/// points meets the target or the ground: a robot that leans on the wall with its base or lands on its tail
/// does not tip over.
bool roomToTip(const Settled& settled, const std::vector<Eigen::Vector3d>& at_contact,
               const TargetBox& target, const std::vector<size_t>& struck, const StrikeBounds& bounds,
               bool backwards) {
  const Eigen::Vector3d n = target.normal(), com = settled.mass.com;
  const double d = backwards ? bounds.rear : bounds.front;
  const Eigen::Vector3d pivot(com.x(), com.y(), settled.ground);
  const Eigen::Vector3d edge = pivot + (backwards ? -d : d) * n;
  const Eigen::Vector3d axis = (backwards ? -1.0 : 1.0) * Eigen::Vector3d::UnitZ().cross(n).normalized();
  // The struck point that stays on the target: the highest for a backward turn, the lowest for a forward one.
  size_t held = struck.front();
  for (size_t i : struck) {
    if ((at_contact[i].z() > at_contact[held].z()) == backwards) held = i;
  }
  const double face = (target.pose.translation() - target.half.x() * n).dot(n);
  const double over = std::atan2(d, bounds.com_height);
  for (double angle = kRoomStep; angle < over; angle += kRoomStep) {
    const Eigen::AngleAxisd turn(angle, axis);
    const Eigen::Vector3d shift = (face - n.dot(edge + turn * (at_contact[held] - edge))) * n;
    for (size_t i = 0; i < at_contact.size(); ++i) {
      const Eigen::Vector3d q = edge + turn * (at_contact[i] - edge) + shift;
      if (target.pastNearFace(q, kRoomTolerance) || q.z() < settled.ground - kRoomTolerance) return false;
    }
  }
  return true;
}

StrikeBounds strikeBounds(const Settled& settled, const std::vector<SurfacePoint>& points, const Drive& drive,
                          const TargetBox& target, const StrikeCell& cell) {
  StrikeBounds bounds;
  const Eigen::Vector3d n = target.normal();
  const double m = settled.mass.mass, weight = m * kGravity;
  bounds.mass = m;
  bounds.com_height = settled.mass.com.z() - settled.ground;
  const Supports supports = supportsOf(settled, points, n);
  bounds.front = supports.front;
  bounds.rear = supports.rear;
  double driven_load = 0, driven_rear = -std::numeric_limits<double>::infinity();
  for (const auto& part : supports.parts) {
    if (!part.driven) continue;
    driven_load += part.load;
    driven_rear = std::max(driven_rear, -part.along);
  }
  bounds.rear_driven = driven_rear > bounds.rear - kRearDrivenTolerance;
  // Where the robot first meets the target: the robot moved there along its heading.
  double first = std::numeric_limits<double>::infinity();
  for (const auto& p : settled.points) first = std::min(first, target.distanceAlong(p, settled.heading));
  std::vector<Eigen::Vector3d> at_contact;
  std::vector<size_t> struck;
  std::vector<int> struck_wheels;
  double height_sum = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    at_contact.push_back(settled.points[i] + first * settled.heading);
    if (target.distanceAlong(settled.points[i], settled.heading) > first + kFirstTouch) continue;
    struck.push_back(i);
    height_sum += settled.points[i].z() - settled.ground;
    if (points[i].driven &&
        std::find(struck_wheels.begin(), struck_wheels.end(), points[i].part) == struck_wheels.end())
      struck_wheels.push_back(points[i].part);
  }
  bounds.contact_height = height_sum / static_cast<double>(struck.size());
  bounds.wheel_first = !struck_wheels.empty();
  // Impact: about the front edge when struck below the centre of mass, the rear one when above.
  const double h = bounds.com_height, lever = h - bounds.contact_height, slant = std::cos(cell.angle);
  const double d = lever > 0 ? bounds.front : bounds.rear;
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ().cross(n).normalized();
  bounds.pitch_inertia = axis.dot(settled.mass.inertia * axis) + m * (d * d + h * h);
  const double omega = m * cell.speed * slant * std::abs(lever) / bounds.pitch_inertia;
  bounds.impact_energy = 0.5 * bounds.pitch_inertia * omega * omega;
  bounds.barrier = weight * (std::hypot(d, h) - h);
  const bool impact_room = roomToTip(settled, at_contact, target, struck, bounds, /*backwards=*/lever < 0);
  if (std::abs(lever) * slant > 1e-9 && impact_room)
    bounds.tip_speed = std::sqrt(2 * bounds.barrier * bounds.pitch_inertia) / (m * std::abs(lever) * slant);
  bounds.impact_tips = impact_room && bounds.impact_energy > bounds.barrier;
  // Stall: the wheels' push against the target's reaction at z_c, lifting the front over the rear edge.
  const double wheels = drive.radius > 0 ? drive.torque * drive.joints.size() / drive.radius : 0.0;
  bounds.push = std::min(settled.friction * weight, wheels) * slant;
  bounds.stall_tips = bounds.rear_driven && bounds.push * bounds.contact_height > weight * bounds.rear &&
                      roomToTip(settled, at_contact, target, struck, bounds, /*backwards=*/true);
  // Climbing: the wall's friction on each struck driven wheel, mu times its share of the wheels' push (what
  // their load lets them push with), against the load on that wheel.
  if (bounds.wheel_first) {
    const double push = std::min(settled.friction * driven_load, wheels) * slant;
    double load = 0;
    for (int part : struck_wheels)
      load = std::max(load, supports.find(part) ? supports.find(part)->load : 0.0);
    bounds.wheel_load = load;
    bounds.climb_ratio = load > 0 ? kWallFriction * push / struck_wheels.size() / load : 0.0;
  }
  return bounds;
}

}  // namespace

namespace {

/// Follows a run step by step: tilt, rise, penetration, path, energy.
class StrikeWatch {
 public:
  StrikeWatch(const Robot& robot, const std::vector<SurfacePoint>& points, const Settled& settled,
              const TargetBox& target)
      : robot_(robot),
        points_(points),
        settled_(settled),
        target_(target),
        last_sample_(settled.root.translation()),
        measured_at_(settled.root),
        sides_(points.size(), -1) {
    first_reach_ = measured_ = std::numeric_limits<double>::infinity();
    for (const auto& p : settled.points) {
      first_reach_ = std::min(first_reach_, target.distanceAlong(p, settled.heading));
      measured_ = std::min(measured_, target.distance(p));
      reach_ = std::max(reach_, (p - settled.root.translation()).norm());
    }
  }

  /// How far the robot still has to go along its heading to meet the target [m], from its travel.
  double approach() const {
    const Eigen::Vector3d root = robot_.body().linkPose(robot_.body().spec().root).translation();
    return first_reach_ - (root - settled_.root.translation()).dot(settled_.heading);
  }

  /// How far the robot is from the target [m]: exact (over every point) when it may be within kNearGap, else
  /// a lower bound from how far it moved and turned since it was last measured.
  double clearance() {
    const Eigen::Isometry3d root = robot_.body().linkPose(robot_.body().spec().root);
    const double turned = Eigen::AngleAxisd(root.linear() * measured_at_.linear().transpose()).angle();
    const double bound =
        measured_ - (root.translation() - measured_at_.translation()).norm() - turned * reach_;
    if (bound > kNearGap) return bound;
    measured_ = std::numeric_limits<double>::infinity();
    for (const auto& p : worldPoints(robot_.body(), points_))
      measured_ = std::min(measured_, target_.distance(p));
    measured_at_ = root;
    return measured_;
  }

  /// After each step.
  void observe(StrikeOutcome& outcome, double time, bool close) {
    const PhysicsRobot& body = robot_.body();
    const Eigen::Isometry3d root = body.linkPose(body.spec().root);
    const Eigen::Vector3d up = root.linear() * settled_.root.linear().transpose().col(2);
    outcome.max_tilt = std::max(outcome.max_tilt, std::acos(std::clamp(up.z(), -1.0, 1.0)));
    outcome.root_rise = std::max(outcome.root_rise, root.translation().z() - settled_.root.translation().z());
    if (close) {
      double lowest = std::numeric_limits<double>::infinity();
      const std::vector<Eigen::Vector3d> points = worldPoints(body, points_);
      Eigen::Vector3d middle = Eigen::Vector3d::Zero();
      for (size_t i = 0; i < points.size(); ++i) {
        middle += points[i] / static_cast<double>(points.size());
        lowest = std::min(lowest, points[i].z());
        outcome.penetration = std::max(outcome.penetration, target_.depth(points[i]));
        // A point that was before the near face crosses to beyond the far face without going round an edge.
        const int side = target_.side(points[i]);
        if (side == 1 && sides_[i] == -1) outcome.through = true;
        if (side != 0 || target_.depth(points[i]) <= 0) sides_[i] = side;
      }
      outcome.rise = std::max(outcome.rise, lowest - settled_.ground);
      // The middle of its surface points lies within the robot; its root frame may not (a base_footprint
      // under the chassis, which a robot on its back leaning on the target holds inside it).
      outcome.through |= !points.empty() && target_.depth(middle) > 0;
    }
    if (time + 1e-9 >= next_sample_) {
      outcome.path += (root.translation() - last_sample_).norm();
      last_sample_ = root.translation();
      next_sample_ += kSamplePeriod;
      outcome.trail.push_back(trailPoint(time, std::acos(std::clamp(up.z(), -1.0, 1.0))));
    }
  }

  static constexpr double kNearGap = 0.05;  ///< [m] closer than this, every point is watched every step

 private:
  StrikeTrailPoint trailPoint(double time, double tilt) const {
    const PhysicsRobot& body = robot_.body();
    const std::string& root = body.spec().root;
    const Eigen::Isometry3d pose = body.linkPose(root);
    StrikeTrailPoint point;
    point.time = time;
    point.position = pose.translation();
    const Eigen::Matrix3d& r = pose.linear();
    point.rpy = Eigen::Vector3d(std::atan2(r(2, 1), r(2, 2)), std::asin(std::clamp(-r(2, 0), -1.0, 1.0)),
                                std::atan2(r(1, 0), r(0, 0)));
    point.linear = body.linkLinearVelocity(root);
    point.angular = body.linkAngularVelocity(root);
    point.tilt = tilt;
    return point;
  }

  const Robot& robot_;
  const std::vector<SurfacePoint>& points_;
  const Settled& settled_;
  const TargetBox& target_;
  double first_reach_;
  double measured_;               ///< [m] the robot's clearance from the target when last measured
  double reach_ = 0;              ///< [m] of its farthest point from its root
  Eigen::Vector3d last_sample_;
  Eigen::Isometry3d measured_at_;  ///< its root's pose then
  std::vector<int> sides_;        ///< per point, the side of the target it was last on (TargetBox::side)
  double next_sample_ = kSamplePeriod;
};

/// The command as the drive ramps it towards `target` [m/s], at most its cap, one step of `dt` on.
double ramped(double command, double target, const Drive& drive, double dt) {
  target = std::min(target, drive.max_speed);
  if (drive.acceleration <= 0) return target;
  return command + std::clamp(target - command, -drive.acceleration * dt, drive.acceleration * dt);
}

/// [m] the robot needs to reach `speed`: at the drive's ramp, or at 0.3 g when it has none.
double runUp(const Drive& drive, double speed) {
  const double acceleration = drive.acceleration > 0 ? drive.acceleration : 0.3 * kGravity;
  return speed * speed / (2 * acceleration) + 0.1;
}

void judge(const StrikeCell& cell, double start_energy, StrikeOutcome& outcome) {
  const StrikeBounds& b = outcome.bounds;
  auto fail = [&](const std::string& what, double value, double limit) {
    std::ostringstream text;
    text << what << " " << value << " (limit " << limit << ")";
    outcome.failures.push_back(text.str());
  };
  if (!outcome.reached) outcome.failures.push_back("never met the target");
  if (outcome.through) outcome.failures.push_back("passed through the target");
  // A robot whose bounds let its wheel climb the wall may fall back down: that fall is gravity's, not a
  // fling.
  const double fall = b.climbs() || b.mayClimb() ? outcome.root_rise : 0.0;
  const double path_limit = outcome.command_path + kFlingSlack + fall;
  if (outcome.path > path_limit) fail("flung: path [m]", outcome.path, path_limit);
  if (cell.coast) {
    outcome.energy_allowance =
        0.5 * b.mass * kCorrectingSpeed * kCorrectingSpeed + kEnergyFraction * std::abs(start_energy);
    if (outcome.energy_gain > outcome.energy_allowance)
      fail("energy gained [J]", outcome.energy_gain, outcome.energy_allowance);
  }
  if (cell.coast) return;  // a coasting robot is judged by its energy
  if (b.mayClimb()) {  // too close to the threshold to say: only no leap
    if (outcome.rise > kMaxRise) fail("leapt [m]", outcome.rise, kMaxRise);
    return;
  }
  // Held square against a wall, a robot keeps pushing and a wheel that can climb does; struck at an angle or
  // at an edge, it slides off, and may or may not.
  const bool held = cell.angle == 0 && cell.target != StrikeTarget::kDoorEdge;
  if (b.climbs() && !held) {
    if (outcome.rise > kMaxRise) fail("leapt [m]", outcome.rise, kMaxRise);
    return;
  }
  if (b.climbs()) {  // climbing is physical: the struck wheel climbs, the robot keeps a wheel on the ground
    if (outcome.max_tilt < kSlowTilt && outcome.root_rise < kClimbed)
      fail("did not climb, though the wall's friction can carry its wheel: tilt [rad]", outcome.max_tilt,
           kSlowTilt);
    if (outcome.rise > kMaxRise) fail("leapt [m]", outcome.rise, kMaxRise);
    return;
  }
  if (b.tips()) {
    const double edge = b.impact_tips ? (b.com_height > b.contact_height ? b.front : b.rear) : b.rear;
    const double over = std::atan2(edge, b.com_height);
    if (outcome.max_tilt < over)
      fail("did not tip over as the bounds say: tilt [rad]", outcome.max_tilt, over);
    return;
  }
  const double tilt = cell.speed <= kSlowSpeed + 1e-9 ? kSlowTilt : kFastTilt;
  if (outcome.max_tilt > tilt) fail("tilted [rad]", outcome.max_tilt, tilt);
  if (outcome.rise > kMaxRise) fail("leapt [m]", outcome.rise, kMaxRise);
}

}  // namespace

namespace {

/// One run of a cell: the simulation with the robot settled and the target placed, then the approach.
class StrikeRun {
 public:
  /// With `given_at_start`, the target stands kGivenGap ahead and the robot gets its speed at once (it
  /// could not reach it by itself).
  StrikeRun(const StrikeRobot& robot, const StrikeCell& cell, const WorldSpec& world, bool given_at_start)
      : robot_(robot),
        cell_(cell),
        parameters_(robot.control_yaml.empty() ? ParameterTree()
                                               : ParameterTree::fromYaml(robot.control_yaml, robot.name)),
        source_(parameters_),
        simulation_(withTarget(world, cell), options(cell, source_)),
        given_at_start_(given_at_start) {
    std::string urdf = withStrikeWheelModel(robot.urdf, cell.wheel_model);
    if (cell.coast) urdf = withMotorsOff(urdf, robot.control_yaml);
    std::vector<std::string> warnings;
    robot_body_ = &simulation_.spawn(
        robot.name, parseModel(urdf, robot.name, PackageResolver::fromEnvironment(), &warnings), SpawnPose{});
    drive_ = driveOf(*robot_body_, parameters_);
    points_ = samplePoints(robot_body_->body(), drive_);
    for (long i = 0; i < std::lround(kSettleTime / cell.step); ++i) {
      if (i % resendSteps() == 0) drive_.command(0, simulation_.time());
      simulation_.step();
    }
    settled_ = settledState(*robot_body_, points_, drive_);
    const double gap = cell.coast       ? kCoastGap
                       : given_at_start ? kGivenGap
                                        : kGivenGap + runUp(drive_, cell.speed);
    target_ = placeTarget(cell, settled_.points, settled_.heading, gap);
    EntityState placed;
    placed.pose = target_.pose;
    const std::string twist_ignored = world_.setModelState("strike_target", placed);
    if (!twist_ignored.empty()) throw std::logic_error("placing the target: " + twist_ignored);
    outcome_.bounds = strikeBounds(settled_, points_, drive_, target_, cell);
  }

  /// Drives the robot in; false when it tipped over before meeting the target or being given its speed.
  bool approach(const StrikeSnapshot& snapshot) {
    StrikeWatch watch(*robot_body_, points_, settled_, target_);
    const double start = simulation_.time(), dt = cell_.step;
    const double deadline = start + 2 * (kGivenGap + runUp(drive_, cell_.speed)) / cell_.speed + 3.0;
    double command = 0;
    bool decided = false, pictured = false;
    while (simulation_.time() < std::min(deadline, contact_time_ + kAfterContact + kWatchAfter)) {
      const bool driving = simulation_.time() < contact_time_ + kAfterContact;
      const double wanted = driving && !cell_.coast ? cell_.speed : 0.0;
      if (std::lround((simulation_.time() - start) / dt) % resendSteps() == 0)
        drive_.command(wanted, simulation_.time());
      if (!decided && (cell_.coast || given_at_start_ || watch.approach() <= kGivenGap)) {
        decided = true;
        if (cell_.coast || given_at_start_ || speedAlongHeading() < kReachedFraction * cell_.speed)
          giveSpeed();
      }
      if (!decided && outcome_.max_tilt > kFastTilt) return false;
      command = ramped(command, wanted, drive_, dt);
      if (outcome_.given_speed && driving) command = std::max(command, cell_.speed);
      if (cell_.coast && !outcome_.given_speed) command = 0;
      simulation_.step();
      outcome_.command_path += command * dt;
      const double clearance = watch.clearance();
      if (!outcome_.reached && clearance <= kFirstTouch) {
        outcome_.reached = true;
        contact_time_ = simulation_.time();
      }
      watch.observe(outcome_, simulation_.time() - start,
                    clearance < StrikeWatch::kNearGap || outcome_.reached);
      if (cell_.coast && outcome_.given_speed)
        energies_.push_back(robotEnergy(*robot_body_, simulation_.world().gravity));
      if (snapshot && !pictured && simulation_.time() >= contact_time_ + kPictureAfter) {
        pictured = true;
        snapshot(simulation_, robot_.name, "contact");
      }
    }
    if (snapshot) snapshot(simulation_, robot_.name, "end");
    outcome_.sim_seconds = simulation_.time() - start;
    outcome_.given_speed |= given_at_start_;
    return true;
  }

  /// The run's figures, judged.
  StrikeOutcome finish() {
    double start_energy = 0;
    if (!energies_.empty()) {  // from 0.1 s before the first contact on
      const long size = static_cast<long>(energies_.size());
      const long contact = size - std::lround((simulation_.time() - contact_time_) / cell_.step);
      const size_t from =
          static_cast<size_t>(std::clamp(contact - std::lround(0.1 / cell_.step), 0L, size - 1));
      start_energy = energies_[from];
      for (size_t i = from; i < energies_.size(); ++i)
        outcome_.energy_gain = std::max(outcome_.energy_gain, energies_[i] - start_energy);
    }
    judge(cell_, start_energy, outcome_);
    return outcome_;
  }

 private:
  static WorldSpec withTarget(WorldSpec world, const StrikeCell& cell) {
    world.models.push_back(targetModel(targetShape(cell)));  // parked far away until the robot has settled
    return world;
  }
  static SimulationOptions options(const StrikeCell& cell, const ParameterSource& parameters) {
    SimulationOptions options;
    options.physics.step_size = cell.step;
    options.parameters = &parameters;
    return options;
  }
  long resendSteps() const { return std::max(1L, std::lround(0.1 / cell_.step)); }
  double speedAlongHeading() const {
    return robot_body_->body().linkLinearVelocity(robot_body_->body().spec().root).dot(settled_.heading);
  }
  /// set_model_state: the robot moves at the cell's speed along its heading.
  void giveSpeed() {
    EntityState given = world_.modelState(robot_.name);
    given.linear = cell_.speed * settled_.heading;
    given.angular.setZero();
    const std::string twist_ignored = world_.setModelState(robot_.name, given);
    if (!twist_ignored.empty()) throw std::logic_error("giving the robot its speed: " + twist_ignored);
    outcome_.given_speed = true;
  }

  const StrikeRobot& robot_;
  const StrikeCell& cell_;
  ParameterTree parameters_;
  TreeParameters source_;
  Simulation simulation_;
  WorldApi world_{simulation_};  ///< set_model_state, as a user's script moves things
  bool given_at_start_;
  Robot* robot_body_ = nullptr;
  Drive drive_;
  std::vector<SurfacePoint> points_;
  Settled settled_;
  TargetBox target_;
  StrikeOutcome outcome_;
  double contact_time_ = std::numeric_limits<double>::infinity();
  std::vector<double> energies_;  ///< coasting: per step, from when it is given its speed
};

}  // namespace

StrikeOutcome runStrike(const StrikeRobot& robot, const StrikeCell& cell, const WorldSpec& world,
                        const StrikeSnapshot& snapshot) {
  const auto started = std::chrono::steady_clock::now();
  std::optional<StrikeOutcome> outcome;
  {
    StrikeRun run(robot, cell, world, /*given_at_start=*/false);
    if (run.approach(snapshot)) outcome = run.finish();
  }
  if (!outcome) {  // it tipped over reaching its speed: given it, as set_model_state does
    StrikeRun run(robot, cell, world, /*given_at_start=*/true);
    run.approach(snapshot);
    outcome = run.finish();
  }
  outcome->wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return *outcome;
}

}  // namespace bullet_sim
