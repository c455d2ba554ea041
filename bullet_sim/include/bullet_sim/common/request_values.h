// The checks a value brought at run time passes at the boundary (a service request, a topic message, an
// action goal): a finite number in every component, a magnitude within its bound, a quaternion that is a
// rotation. Each throws std::invalid_argument naming the field and the value; the caller turns that into its
// refusal.
#pragma once

#include <Eigen/Geometry>

#include <string>

namespace bullet_sim {

/// The largest magnitude of a command: a joint position [rad or m], velocity, acceleration or effort, a
/// velocity command [m/s or rad/s]. Far beyond any robot's, and far below where a controller's arithmetic
/// overflows.
constexpr double kMaxCommand = 1e6;

/// "<field> [<value>] is not finite" unless `value` is finite.
void requireFinite(double value, const std::string& field);
/// Each component: "<field>.y [nan] is not finite".
void requireFinite(const Eigen::Vector3d& vector, const std::string& field);
/// Finite, and |value| <= `bound` [unit]: "<field> [1e+308 N] is beyond the 1e+12 N bullet_sim takes".
void requireWithin(double value, double bound, const std::string& field, const std::string& unit);
/// Each component (not a norm, which a NaN or an overflow slips past).
void requireWithin(const Eigen::Vector3d& vector, double bound, const std::string& field,
                   const std::string& unit);
/// The rotation the quaternion (x, y, z, w) `field` means, normalised. All four 0 (a message's unset
/// orientation) mean no rotation, as in Gazebo. Throws when a component is not finite, or when the norm is
/// below 1e-6 or above 1e6: such a quaternion underflows or overflows as it is normalised, and is no rotation
/// anyone meant.
Eigen::Quaterniond requireRotation(double x, double y, double z, double w, const std::string& field);

}  // namespace bullet_sim
