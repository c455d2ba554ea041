// Bounds on what a description may ask of the simulator, so that no file can exhaust the machine or hand a
// value to Bullet or Embree that breaks them. Each is a parameter: the simulator's ~limits/<name>, the tools'
// --limit <name>=<value>. The defaults are far above any real robot's and world's needs.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

struct Limits {
  // Counts and sizes: beyond them a file is refused, with an error naming the value and the limit.
  size_t max_description_bytes = 64u << 20;  ///< of a URDF's text
  size_t max_links = 1000;                   ///< of one robot
  /// Of one robot. A Bullet multibody's contacts cost O(joints) each: a fallen chain of 1000 links takes
  /// about 0.1 s per 1 ms step, one of 300 about 2 ms.
  size_t max_moving_joints = 256;
  size_t max_shapes = 10000;              ///< collisions and visuals of one robot
  size_t max_world_shapes = 200000;       ///< collisions and visuals of a world
  size_t max_mesh_bytes = 256u << 20;     ///< of one mesh file (an OBJ's .mtl included)
  size_t max_triangles = 10000000;        ///< of all the meshes of one robot, or of a world
  size_t max_rays = 1u << 20;             ///< per scan of one lidar (samples x resolution x channels)
  size_t max_image_pixels = 4096 * 4096;  ///< of one camera image
  double max_length = 1e4;                ///< [m] of any size, position, distance or range
  double max_mass = 1e6;                  ///< [kg] of one link
  double max_inertia = 1e9;               ///< [kg m^2] of one moment or product of inertia
  double mesh_import_seconds = 30;        ///< [s] of wall time for importing one mesh file
  /// [s] of wall time for splitting one moving collision mesh into convex parts; beyond it, its hull is used
  double decomposition_seconds = 60;
  size_t max_convex_parts = 32;  ///< of one moving collision mesh; 1 collides by the mesh's hull
  double world_load_seconds = 120;        ///< [s] of wall time for reading a world (10,000 boxes: 0.3 s)
  // Values Gazebo accepts: beyond them, a warning names the value and the limit is used instead.
  double max_effort = 1e6;  ///< [N m] or [N]: joint effort limits, drive torques
  double max_rate = 1e4;    ///< [Hz]: update rates

  /// The limit called `name` (a field above, e.g. "max_links"). Throws std::invalid_argument naming the
  /// limits there are when `name` is none of them, or when `value` is not a positive finite number.
  void set(const std::string& name, double value);
  /// Every limit's name, in the order above.
  static std::vector<std::string> names();
  /// Its value as a number; nullopt for an unknown name.
  std::optional<double> get(const std::string& name) const;
};

/// "[value] <unit> is above the limit of <limit> <unit> (<name>)": the tail of a refusal.
std::string aboveLimit(double value, const char* name, const Limits& limits, const std::string& unit = "");

/// The first problem of a number read from a description: not finite, or of a magnitude above `bound`.
/// nullopt when it is fine.
std::optional<std::string> boundProblem(double value, double bound, const char* limit_name,
                                        const std::string& unit);

}  // namespace bullet_sim
