// Cameras of the offscreen renderer, in the world frame (x east, y north, z up) [m]: a perspective camera for
// views around a robot and an orthographic one looking straight down for plans.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <optional>
#include <string>

namespace bullet_sim {

struct Camera {
  enum class Projection { kPerspective, kOrthographic };
  Projection projection = Projection::kPerspective;

  // Perspective.
  Eigen::Vector3d eye{-3, 0, 2};                     ///< [m]
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< the point at the image centre [m]
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();     ///< the world direction that appears upwards
  double vertical_fov = 45 * M_PI / 180;             ///< [rad]
  /// [m] along the view axis: nothing nearer is drawn. Views around a robot put it just in front of the
  /// robot, so that a wall between the camera and the robot is cut away instead of hiding it.
  double near_clip = 0.05;
  double far_clip = 500;  ///< [m] along the view axis: nothing farther is drawn (well past the 100 m ground)

  // Orthographic, looking down -z with +x to the right and +y up in the image.
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< world x, y at the image centre [m]
  /// World half width (x) and half height (y) that the image shows at least [m]; when the image's aspect
  /// differs, it shows more along one axis so that pixels stay square.
  Eigen::Vector2d half_extents{5, 5};

  static Camera perspective(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                            const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ(),
                            double vertical_fov = 45 * M_PI / 180);
  static Camera topDown(const Eigen::Vector2d& centre, const Eigen::Vector2d& half_extents);

  /// World frame to OpenGL eye coordinates (camera looking down its -z, y up).
  Eigen::Matrix4d viewMatrix() const;
  /// Eye coordinates to clip coordinates for an image of `aspect` = width / height.
  Eigen::Matrix4d projectionMatrix(double aspect) const;
  /// The distance along the view axis [m] of a depth buffer value in [0, 1] (OpenGL's default depth range).
  double viewDepth(double window) const;
  /// viewDepth as the fraction (p + q w) / (r + s w) of the depth buffer value w: (p, q, r, s), for whole
  /// buffers.
  Eigen::Vector4d viewDepthFraction() const;
  /// Where a world point appears in a width x height image: (column, row) in pixels from the image's top-left
  /// corner, so pixel (c, r) covers [c, c + 1) x [r, r + 1). Nullopt for a point behind a perspective camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& point, int width, int height) const;
};

/// The views render_model offers.
enum class View { kChase, kTop, kFront };

/// "chase", "top" or "front"; nullopt for anything else.
std::optional<View> parseView(const std::string& name);

/// Behind and above a robot, looking at the centre of its bounds. The distance grows with the robot's size,
/// so that any robot covers about the same share of the image. `robot_pose`'s x axis is the robot's heading.
Camera chaseCamera(const Eigen::Isometry3d& robot_pose, const Eigen::AlignedBox3d& robot_bounds);

/// In front of a robot and above it, looking back at it; otherwise as chaseCamera.
Camera frontCamera(const Eigen::Isometry3d& robot_pose, const Eigen::AlignedBox3d& robot_bounds);

/// An orthographic plan that shows the x-y extent of `bounds` with a small margin.
Camera topCamera(const Eigen::AlignedBox3d& bounds);

/// A perspective camera at `pose`, looking along the pose's x axis with its z axis up (a ROS body frame).
Camera cameraAt(const Eigen::Isometry3d& pose, double vertical_fov = 45 * M_PI / 180);

/// The camera of `view`: chase and front frame the robot, top frames the world's obstacles and the robot.
Camera viewCamera(View view, const Eigen::Isometry3d& robot_pose, const Eigen::AlignedBox3d& robot_bounds,
                  const Eigen::AlignedBox3d& world_bounds);

}  // namespace bullet_sim
