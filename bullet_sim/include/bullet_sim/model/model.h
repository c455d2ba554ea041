// A robot model: URDF links and joints plus Gazebo's <gazebo> extensions, validated and immutable.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/model/geometry.h"
#include "bullet_sim/common/limits.h"
#include "bullet_sim/assets/package_resolver.h"
#include "bullet_sim/model/plugin_declaration.h"
#include "bullet_sim/model/transmission.h"

namespace bullet_sim {

class Diagnostics;

struct InertialSpec {
  double mass = 0;                                    ///< [kg]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      ///< centre of mass in the link frame [m]
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  ///< about the com, in link-frame axes [kg m^2]
};

/// Contact properties from <gazebo reference="link">; defaults are Gazebo's.
struct SurfaceSpec {
  /// A negative mu, as Gazebo's FrictionPyramid::SetMu reads it (GZ_FLT_MAX): the other surface's decides.
  static constexpr double kUnlimitedMu = 3.402823466e+38;
  /// What a warning about a negative mu says of it.
  static constexpr const char* kNegativeMuReading =
      "read as unlimited friction, so the other surface's mu decides, as Gazebo reads it";
  double mu1 = 1.0;          ///< friction coefficient along the first friction direction
  double mu2 = 1.0;          ///< and the second
  std::optional<double> kp;  ///< contact stiffness [N/m]
  std::optional<double> kd;  ///< contact damping [N s/m]
};

struct LinkSpec {
  std::string name;
  std::optional<InertialSpec> inertial;
  std::vector<Collision> collisions;
  std::vector<Visual> visuals;
  SurfaceSpec surface;
  bool self_collide = false;
  bool gravity = true;
};

/// An axis no longer than this sdformat 12 calls zero (JointAxis::SetXyz); Gazebo's ODE normalizes it.
constexpr double kShortestAxis = 1e-6;

struct JointSpec {
  enum class Type { kFixed, kRevolute, kContinuous, kPrismatic };
  std::string name;
  Type type = Type::kFixed;
  std::string parent;
  std::string child;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< child frame in the parent frame at q = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           ///< unit, in the child frame
  double lower = -std::numeric_limits<double>::infinity();   ///< [rad] or [m]
  double upper = std::numeric_limits<double>::infinity();
  double effort = 0;    ///< [N m] or [N]; 0 = no limit given
  double velocity = 0;  ///< [rad/s] or [m/s]; 0 = no limit given
  double damping = 0;   ///< [N m s/rad]
  double friction = 0;  ///< [N m]
  /// <disableFixedJointLumping> or <preserveFixedJoint>: Gazebo keeps a fixed joint's child link apart
  /// instead of lumping it into the parent (which changes the names of its collisions, not its physics).
  bool lumping_disabled = false;
  /// URDF's <mimic>, or a mimic joint plugin's: this joint follows another, held at multiplier * its
  /// position + offset by a coupling as strong as `max_effort`.
  struct Mimic {
    std::string joint;  ///< the joint it follows
    double multiplier = 1;
    double offset = 0;     ///< [rad] or [m]
    double max_effort = 0;  ///< [N m] or [N]
    std::string source;     ///< who asked for it, for messages: "<mimic>" or a plugin's where()
  };
  std::optional<Mimic> mimic;

  bool moves() const { return type != Type::kFixed; }
};

struct ModelSpec {
  std::string name;
  /// Gazebo's <static>: the model is rigid and never moves by itself (only when teleported); its links need
  /// no mass.
  bool is_static = false;
  /// Gazebo's <allow_auto_disable>: a body of one link may sleep at rest (physics/sleep.h says when).
  bool allow_auto_disable = true;
  /// The root link's frame in the model frame, whose pose is the model's (Gazebo's Model::WorldPose): an SDF
  /// model's root link <pose>; identity for a URDF.
  Eigen::Isometry3d root_in_model = Eigen::Isometry3d::Identity();
  /// The model frame where its file puts it: an SDF model's <pose>, which a spawn composes with its initial
  /// pose, as Gazebo does; identity for a URDF.
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  std::string source;             ///< where the URDF came from, for messages
  /// Read from SDF (sdf_model.h): Gazebo names its links and collisions as the file does. A URDF's
  /// collisions are named by Gazebo's URDF conversion ("link_collision"), and fixed joints lump its links.
  bool names_from_sdf = false;
  std::string root;               ///< root link
  std::vector<LinkSpec> links;    ///< the root first, then parents before children
  std::vector<JointSpec> joints;  ///< in the order of `links` (joint i + 1 leads to links[i + 1])
  /// The plugins bullet_sim simulates, typed: the model's own <gazebo><plugin>s first, then the sensors'.
  std::vector<PluginDeclaration> plugins;
  /// The <transmission>s ros_control would load (for libgazebo_ros_control.so), in the file's order.
  std::vector<TransmissionSpec> transmissions;

  const LinkSpec* link(const std::string& name) const;
  const JointSpec* joint(const std::string& name) const;
  JointSpec* joint(const std::string& name);
  /// The joint whose child is `link`, or nullptr for the root.
  const JointSpec* parentJoint(const std::string& link) const;
  std::vector<std::string> linkNames() const;
  std::vector<std::string> jointNames() const;
};

/// A <plugin> of a model description, on its own or inside a <sensor>, as found: what declarePlugins reads.
struct PluginElement {
  TagNode plugin;
  std::optional<SensorDeclaration> sensor;  ///< the sensor it is in, if any,
  std::optional<TagNode> sensor_tags;       ///< and that sensor's element
  std::string where;                        ///< where it was found, the head of messages (e.g. "line 12: ")
};

/// Types each element with `plugins` into model.plugins, in order; one that bullet_sim does not simulate is
/// left out after the parser's warning, and one without a filename is an error; then checks what the plugins
/// ask together and what they add to its joints (PluginParsers::completeModel). The model's links and joints
/// must be complete: plugins name them.
void declarePlugins(const std::vector<PluginElement>& elements, const PluginParsers& plugins,
                    ModelSpec& model, Diagnostics& diagnostics, const Limits& limits);

/// Parses a URDF string with its <gazebo> tags; `plugins` turns each <plugin> into its typed config (the
/// plugin registry's parseModel overload passes the built-in plugins). Throws SpecError naming `source` and
/// listing every problem, of whatever kind (malformed XML with line number, urdfdom's complaint, a link with
/// two parents or cut off from the root, a number that is not finite or beyond `limits`, a negative mass, too
/// many links or shapes, missing collision meshes, references to missing links, bad plugin tags). What
/// Gazebo accepts is a warning, appended to `warnings` when given: ignored tags, plugins not simulated, a
/// missing visual mesh (not drawn), a frame naming no link (used as the frame_id), a body with no mass or a
/// poor inertia (lumped as Gazebo does, then given a solid box's), transmissions nothing reads, a <gazebo
/// reference> naming nothing (skipped). With `strict` (~strict_models), what Gazebo forgives without a word
/// (the last) is an error.
ModelSpec parseModel(const std::string& urdf_xml, const std::string& source, const PackageResolver& resolver,
                     const PluginParsers& plugins, std::vector<std::string>* warnings = nullptr,
                     const Limits& limits = Limits(), bool strict = false);

/// What parseModel reads, for tools that report problems instead of loading (urdf_doctor): never throws;
/// every error and warning goes to `diagnostics`, and the model comes back as far as it could be read (a
/// collision or visual whose mesh cannot be loaded is left out). nullopt when there is no model to read:
/// malformed XML, a root element other than <robot>, a count parseModel refuses, urdfdom rejected the file
/// (often over a number already refused), or its joints do not form a tree.
std::optional<ModelSpec> readModel(const std::string& urdf_xml, const PackageResolver& resolver,
                                   const PluginParsers& plugins, Diagnostics& diagnostics,
                                   const Limits& limits = Limits());

}  // namespace bullet_sim
