// urdf_doctor's checks: what in a URDF makes Gazebo (or bullet_sim) misbehave without saying so. ROS-free.
//
// Beyond what the loader (readModel) refuses or warns about, with its own code and messages (malformed XML,
// urdfdom's complaints, missing meshes, NaN, zero, negative and absurd numbers, the plugins' tags, unexpanded
// macro calls, <gazebo reference> to a missing link, invalid inertia, massless moving links), it finds:
//   - a base_footprint root whose robot does not stand on z = 0 (it falls or sinks at spawn in Gazebo);
//   - what each plugin's own check finds (PluginType::check, in the plugin's folder): drive wheels of a diff
//     drive or skid steer that roll backwards, zero effort or velocity limits on a joint the plugin drives;
//   - mirrored wheels, found from the geometry, whose axes disagree (a drive plugin's own wheels are its
//     check's);
//   - frameName, bodyName and robotBaseFrame tags naming no link;
//   - revolute limits beyond 2 pi (degrees written where URDF wants radians), and revolute or prismatic
//     limits that are equal (the joint cannot move) or inverted;
//   - inertia far from that of the link's collision shapes, and masses denser than any material;
//   - collisions nowhere near their visuals (the seeds' collision origins that repeat the joint origin),
//     and a primitive collision of another shape than its visual;
//   - characters such as U+00A0 (a non-breaking space from a web page), with line and column.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/common/limits.h"
#include "bullet_sim/assets/package_resolver.h"

namespace bullet_sim {

class PluginRegistry;

struct DoctorFinding {
  enum class Severity { kWarning, kError };
  Severity severity = Severity::kError;
  std::string message;  ///< the element, what is wrong, and the fix
};

struct DoctorReport {
  std::string source;
  /// False when the text could not be read, expanded or parsed as XML, or is no URDF: nothing was checked.
  bool readable = true;
  std::vector<DoctorFinding> findings;

  size_t errors() const;
  size_t warnings() const;
  /// urdf_doctor's exit code: 0 clean or warnings only, 1 errors (or warnings, when they count as errors:
  /// --warnings-as-errors), 2 not readable.
  int exitCode(bool warnings_as_errors = false) const;
  /// One "source: error: ..." or "source: warning: ..." line per finding, then a summary line.
  std::string text() const;
};

/// Examines a URDF (xacro already expanded) with its <gazebo> tags; `source` names it in messages. Whatever
/// the simulator refuses under `limits` is an error here, with the same message. Never throws for anything
/// in the text.
DoctorReport examineUrdf(const std::string& urdf_xml, const std::string& source,
                         const PackageResolver& resolver, const Limits& limits = Limits());
/// The same with the plugin types of `registry` (their parsers and their checks) instead of the built-in
/// ones.
DoctorReport examineUrdf(const std::string& urdf_xml, const std::string& source,
                         const PackageResolver& resolver, const Limits& limits,
                         const PluginRegistry& registry);

/// The report for a file that could not be read or expanded: `reason` is its one finding, exit code 2.
DoctorReport unreadableReport(const std::string& source, const std::string& reason);

}  // namespace bullet_sim
