#include "bullet_sim/scene/camera.h"

#include <algorithm>

namespace bullet_sim {

namespace {

// The plan camera floats this high [m] and sees everything within this distance of z = 0.
constexpr double kTopDownHeight = 1000;
constexpr double kViewFov = 45 * M_PI / 180;
constexpr double kViewElevation = 35 * M_PI / 180;  // [rad] of the line of sight above the horizon
// The camera stands this many robot radii (half the bounds' diagonal) from the robot's centre, divided by
// tan(fov / 2): at 1, the robot's bounding sphere would just fill the image height.
constexpr double kFramingRadii = 1.7;
// The near clip plane stays this many robot radii in front of the robot's centre, to keep all of the robot.
constexpr double kCutawayRadii = 1.5;
constexpr double kPlanMargin = 0.25;  // [m] around what a plan must show

Camera aroundRobot(const Eigen::Isometry3d& robot_pose, const Eigen::AlignedBox3d& robot_bounds,
                   double side) {
  Eigen::Vector3d heading = robot_pose.linear().col(0);
  heading.z() = 0;
  // A robot standing on its nose or tail has no heading on the ground; look along world x then.
  heading = heading.norm() > 1e-6 ? heading.normalized() : Eigen::Vector3d::UnitX();
  const bool has_bounds = !robot_bounds.isEmpty();
  const Eigen::Vector3d centre =
      has_bounds ? Eigen::Vector3d(robot_bounds.center()) : robot_pose.translation();
  const double radius = has_bounds ? std::max(0.5 * robot_bounds.diagonal().norm(), 0.05) : 0.5;
  const double distance = kFramingRadii * radius / std::tan(kViewFov / 2);
  const Eigen::Vector3d direction =
      side * std::cos(kViewElevation) * heading + std::sin(kViewElevation) * Eigen::Vector3d::UnitZ();
  Camera camera =
      Camera::perspective(centre + distance * direction, centre, Eigen::Vector3d::UnitZ(), kViewFov);
  camera.near_clip = std::max(distance - kCutawayRadii * radius, camera.near_clip);
  return camera;
}

}  // namespace

Camera Camera::perspective(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                           const Eigen::Vector3d& up, double vertical_fov) {
  Camera camera;
  camera.projection = Projection::kPerspective;
  camera.eye = eye;
  camera.target = target;
  camera.up = up;
  camera.vertical_fov = vertical_fov;
  return camera;
}

Camera Camera::topDown(const Eigen::Vector2d& centre, const Eigen::Vector2d& half_extents) {
  Camera camera;
  camera.projection = Projection::kOrthographic;
  camera.centre = centre;
  camera.half_extents = half_extents;
  return camera;
}

Eigen::Matrix4d Camera::viewMatrix() const {
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  if (projection == Projection::kOrthographic) {
    // Eye axes are the world's: x right, y up, looking down -z from high above the centre.
    view.block<3, 1>(0, 3) = -Eigen::Vector3d(centre.x(), centre.y(), kTopDownHeight);
    return view;
  }
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d right = forward.cross(up).normalized();
  const Eigen::Vector3d camera_up = right.cross(forward);
  view.block<1, 3>(0, 0) = right.transpose();
  view.block<1, 3>(1, 0) = camera_up.transpose();
  view.block<1, 3>(2, 0) = -forward.transpose();
  view.block<3, 1>(0, 3) = -view.block<3, 3>(0, 0) * eye;
  return view;
}

Eigen::Matrix4d Camera::projectionMatrix(double aspect) const {
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Zero();
  if (projection == Projection::kOrthographic) {
    const double half_width = std::max(half_extents.x(), half_extents.y() * aspect);
    const double half_height = half_width / aspect;
    const double near = 0, far = 2 * kTopDownHeight;
    matrix(0, 0) = 1 / half_width;
    matrix(1, 1) = 1 / half_height;
    matrix(2, 2) = -2 / (far - near);
    matrix(2, 3) = -(far + near) / (far - near);
    matrix(3, 3) = 1;
    return matrix;
  }
  const double focal = 1 / std::tan(vertical_fov / 2);
  const double near = near_clip, far = std::max(far_clip, 2 * near_clip);
  matrix(0, 0) = focal / aspect;
  matrix(1, 1) = focal;
  matrix(2, 2) = (far + near) / (near - far);
  matrix(2, 3) = 2 * far * near / (near - far);
  matrix(3, 2) = -1;
  return matrix;
}

double Camera::viewDepth(double window) const {
  const Eigen::Vector4d fraction = viewDepthFraction();
  return (fraction[0] + fraction[1] * window) / (fraction[2] + fraction[3] * window);
}

Eigen::Vector4d Camera::viewDepthFraction() const {
  if (projection == Projection::kOrthographic) return {0, 2 * kTopDownHeight, 1, 0};
  // The inverse of projectionMatrix's depth: with ndc = 2 w - 1, 2 f n / ((f + n) - ndc (f - n)).
  const double near = near_clip, far = std::max(far_clip, 2 * near_clip);
  return {far * near, 0, far, -(far - near)};
}

std::optional<Eigen::Vector2d> Camera::project(const Eigen::Vector3d& point, int width, int height) const {
  const Eigen::Vector4d clip =
      projectionMatrix(static_cast<double>(width) / height) * viewMatrix() * point.homogeneous();
  if (clip.w() <= 0) return std::nullopt;
  const Eigen::Vector2d ndc = clip.head<2>() / clip.w();
  return Eigen::Vector2d((ndc.x() + 1) / 2 * width, (1 - ndc.y()) / 2 * height);
}

std::optional<View> parseView(const std::string& name) {
  if (name == "chase") return View::kChase;
  if (name == "top") return View::kTop;
  if (name == "front") return View::kFront;
  return std::nullopt;
}

Camera chaseCamera(const Eigen::Isometry3d& robot_pose, const Eigen::AlignedBox3d& robot_bounds) {
  return aroundRobot(robot_pose, robot_bounds, -1);
}

Camera frontCamera(const Eigen::Isometry3d& robot_pose, const Eigen::AlignedBox3d& robot_bounds) {
  return aroundRobot(robot_pose, robot_bounds, +1);
}

Camera topCamera(const Eigen::AlignedBox3d& bounds) {
  if (bounds.isEmpty()) return Camera::topDown(Eigen::Vector2d::Zero(), Eigen::Vector2d(5, 5));
  const Eigen::Vector2d half = 0.5 * bounds.sizes().head<2>() + Eigen::Vector2d::Constant(kPlanMargin);
  return Camera::topDown(bounds.center().head<2>(), half);
}

Camera cameraAt(const Eigen::Isometry3d& pose, double vertical_fov) {
  return Camera::perspective(pose.translation(), pose.translation() + pose.linear().col(0),
                             pose.linear().col(2), vertical_fov);
}

Camera viewCamera(View view, const Eigen::Isometry3d& robot_pose, const Eigen::AlignedBox3d& robot_bounds,
                  const Eigen::AlignedBox3d& world_bounds) {
  switch (view) {
    case View::kChase:
      return chaseCamera(robot_pose, robot_bounds);
    case View::kFront:
      return frontCamera(robot_pose, robot_bounds);
    case View::kTop:
      return topCamera(world_bounds.merged(robot_bounds));
  }
  return chaseCamera(robot_pose, robot_bounds);
}

}  // namespace bullet_sim
