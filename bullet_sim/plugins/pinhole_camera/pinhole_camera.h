// Cameras: <sensor type="camera"> with libgazebo_ros_camera.so, and <sensor type="depth"> with
// libgazebo_ros_openni_kinect.so or libgazebo_ros_depth_camera.so, as gazebo_plugins has them on Noetic.
// Their plugin tags are the tag tables in pinhole_camera.cpp; README.md describes the sensor's <camera>
// block, the topics (<cameraName>/<topic> in the plugin's namespace) and what the images hold. A camera
// renders only when someone wants one of its images, on its update timer in sim time, after the physics step.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/plugins/sensor_interfaces.h"

namespace bullet_sim {

struct PinholeCameraConfig : PluginConfig {
  int width = 320;                                         ///< [px]
  int height = 240;
  double horizontal_fov = 1.047;  ///< [rad]
  double near_clip = 0.1;         ///< [m]
  double far_clip = 100;
  std::string encoding = "rgb8";  ///< of the colour image: rgb8, bgr8, mono8, rgb16 or mono16
  double noise_mean = 0;          ///< on colour values in [0, 1]
  double noise_stddev = 0;

  std::string camera_name;
  std::string image_topic;
  std::string info_topic;
  std::string frame;
  double hack_baseline = 0;  ///< [m]; P[3] = -focal * hack_baseline
  double focal_length = 0;   ///< [px]; 0 = width / (2 tan(fov / 2))
  double cx = 0;             ///< [px]; 0 = (width + 1) / 2, as Gazebo has it
  double cy = 0;             ///< [px]; 0 = (height + 1) / 2
  std::array<double, 5> distortion{};  ///< k1, k2, t1, t2, k3 (camera_info's D)

  bool depth = false;  ///< a depth camera: also a depth image and an organized cloud
  std::string depth_topic;
  std::string depth_info_topic;
  std::string points_topic;
  double cloud_cutoff = 0;      ///< [m]: depths at or below it are NaN
  double cloud_cutoff_max = 0;  ///< [m]: depths at or above it are NaN
  bool depth_16uc1 = false;     ///< depth in 16UC1 millimetres instead of 32FC1 metres

  /// Whether a depth [m] is inside (pointCloudCutoff, pointCloudCutoffMax): kept in the depth image and
  /// cloud.
  bool withinCutoffs(double depth) const { return depth > cloud_cutoff && depth < cloud_cutoff_max; }
  /// The focal length [px] the image is rendered with: width / (2 tan(horizontal_fov / 2)).
  double renderedFocalLength() const;
  /// camera_info as gazebo_plugins fills it (K, P from the focal length and centre, D from the tags).
  CameraInfo info() const;
};

/// libgazebo_ros_camera.so on a camera (or wideanglecamera, drawn as a pinhole) sensor.
void parseCamera(const DeclarationSource& source, PinholeCameraConfig& config);
/// libgazebo_ros_openni_kinect.so or libgazebo_ros_depth_camera.so on a depth sensor.
void parseDepthCamera(const DeclarationSource& source, PinholeCameraConfig& config);

class PinholeCamera : public Plugin, public CameraSensor {
 public:
  PinholeCamera(const PluginDeclaration& declaration, const PinholeCameraConfig& config,
                const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const PinholeCameraConfig& config() const { return config_; }
  /// What it asks its image source for at `body`'s current pose, with or without depth.
  ImageRequest imageRequest(const RobotBody& body, bool depth) const override;
  const std::string& cameraName() const override { return config_.camera_name; }
  bool measuresDepth() const override { return config_.depth; }
  std::pair<double, double> depthSpan() const override {
    return {config_.near_clip, std::min(config_.far_clip, config_.cloud_cutoff_max)};
  }

 private:
  void publishImage(const RenderedImage& rendered, double stamp);
  void publishDepth(const RenderedImage& rendered, double stamp);
  void publishCloud(const RenderedImage& rendered, double stamp);
  /// Adds the sensor's colour noise, seeded.
  void addNoise(RenderedImage& rendered);

  PinholeCameraConfig config_;
  ImageSource* images_;
  RenderedImage frame_;        ///< the last frame rendered; its buffers are reused
  std::vector<float> ray_x_;  ///< per column, x / z of its ray through the pixel centre
  Demand image_demand_, depth_demand_, cloud_demand_;
  Stream<CameraImage> image_, depth_;
  Stream<CameraInfo> info_, depth_info_;
  Stream<ColouredCloud> cloud_;
};

}  // namespace bullet_sim
