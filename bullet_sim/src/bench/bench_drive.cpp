#include "bench/bench_drive.h"

#include <time.h>

#include <algorithm>
#include <cmath>

#include "tools/command_line.h"

namespace bullet_sim {

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double threadCpuSeconds() {
  timespec time{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &time);
  return static_cast<double>(time.tv_sec) + static_cast<double>(time.tv_nsec) * 1e-9;
}

double processCpuSeconds() {
  timespec time{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &time);
  return static_cast<double>(time.tv_sec) + static_cast<double>(time.tv_nsec) * 1e-9;
}

double median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const size_t middle = values.size() / 2;
  return values.size() % 2 ? values[middle] : (values[middle - 1] + values[middle]) / 2;
}

Drive driveOf(const Robot& robot, const std::string& source) {
  const auto& declarations = robot.body().spec().plugins;
  for (size_t i = 0; i < declarations.size() && i < robot.plugins().size(); ++i) {
    const PluginType* type = PluginRegistry::builtin().typeOf(declarations[i]);
    if (!type || !type->driven) continue;
    DrivenJoints joints = type->driven(declarations[i]);
    if (!joints.drive || joints.left_wheels.empty()) continue;
    for (const RobotInput<Twist>& input : robot.inputs<Twist>()) {
      if (input.plugin == robot.plugins()[i].get()) return {std::move(joints), input.handler};
    }
  }
  throw Failure(source +
                " has no libgazebo_ros_diff_drive.so or libgazebo_ros_skid_steer_drive.so plugin: bench "
                "drives the robot through one");
}

Planar axlePose(const Robot& robot, const DrivenJoints& drive) {
  const RobotBody& body = robot.body();
  const ModelSpec& spec = body.spec();
  const Eigen::Isometry3d base = body.linkPose(spec.link(drive.base_frame) ? drive.base_frame : spec.root);
  std::vector<std::string> joints = drive.left_wheels;
  joints.insert(joints.end(), drive.right_wheels.begin(), drive.right_wheels.end());
  Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();
  for (const auto& joint : joints) {
    midpoint +=
        (base.inverse() * body.linkPose(body.spec().joint(joint)->child)).translation() / joints.size();
  }
  midpoint.z() = 0;
  const Eigen::Isometry3d axle = base * Eigen::Translation3d(midpoint);
  return {axle.translation().x(), axle.translation().y(),
          std::atan2(axle.linear()(1, 0), axle.linear()(0, 0))};
}

Planar unicycle(const Planar& start, double v, double w, double seconds) {
  const double yaw = start.yaw + w * seconds;
  if (std::abs(w) < 1e-12) {
    return {start.x + v * seconds * std::cos(start.yaw), start.y + v * seconds * std::sin(start.yaw), yaw};
  }
  return {start.x + v / w * (std::sin(yaw) - std::sin(start.yaw)),
          start.y - v / w * (std::cos(yaw) - std::cos(start.yaw)), yaw};
}

}  // namespace bullet_sim
