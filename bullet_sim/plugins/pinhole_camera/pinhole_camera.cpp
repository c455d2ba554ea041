#include "plugins/pinhole_camera/pinhole_camera.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace bullet_sim {

namespace {

constexpr int kMaxImageSide = 16384;  // [px], the renderer's largest

struct Format {
  const char* sdf;
  const char* encoding;
};

// SDF's image formats that gazebo_ros_camera publishes, with their ROS encodings.
constexpr Format kFormats[] = {{"R8G8B8", "rgb8"},     {"RGB_INT8", "rgb8"},    {"B8G8R8", "bgr8"},
                               {"BGR_INT8", "bgr8"},   {"L8", "mono8"},         {"L_INT8", "mono8"},
                               {"L16", "mono16"},      {"L_INT16", "mono16"},   {"R16G16B16", "rgb16"},
                               {"RGB_INT16", "rgb16"}};

std::string encodingOf(const std::string& format, const std::string& where, Diagnostics& diagnostics) {
  for (const Format& known : kFormats) {
    if (format == known.sdf) return known.encoding;
  }
  diagnostics.warning(where + " <format> [" + format +
                      "] is not simulated (Bayer and float formats are not): the image is rgb8 (R8G8B8)");
  return "rgb8";
}

/// A topic under the camera's name, as gazebo_ros_camera_utils advertises it; an absolute topic stays.
std::string underCamera(const std::string& camera_name, const std::string& topic) {
  if (camera_name.empty() || (!topic.empty() && topic.front() == '/')) return topic;
  return camera_name + "/" + topic;
}

void readImageTags(const TagNode* camera, const std::string& where, PinholeCameraConfig& config,
                   Diagnostics& diagnostics) {
  PluginTags image(camera ? camera->child("image") : nullptr, where + " <image>", diagnostics);
  const double width = image.positive("width", config.width);
  const double height = image.positive("height", config.height);
  const std::string format = image.text("format", "R8G8B8");
  image.finish();
  if (width > kMaxImageSide || height > kMaxImageSide) {
    diagnostics.error(where + " <image> of " + std::to_string(width) + " x " + std::to_string(height) +
                      " px is too large: each side must be at most " + std::to_string(kMaxImageSide));
  } else {
    config.width = std::max(1, static_cast<int>(std::lround(width)));
    config.height = std::max(1, static_cast<int>(std::lround(height)));
  }
  config.encoding = encodingOf(format, where, diagnostics);
}

/// SDF's <distortion> coefficients, in camera_info's order (k1, k2, p1, p2, k3).
std::array<double, 5> readDistortion(const TagNode* camera, const std::string& where,
                                     Diagnostics& diagnostics) {
  std::array<double, 5> coefficients{};
  const TagNode* node = camera ? camera->child("distortion") : nullptr;
  if (!node) return coefficients;
  PluginTags distortion(node, where + " <distortion>", diagnostics);
  const char* names[] = {"k1", "k2", "p1", "p2", "k3"};
  for (size_t i = 0; i < coefficients.size(); ++i) coefficients[i] = distortion.number(names[i], 0);
  distortion.accept({"center"});
  distortion.finish();
  if (std::any_of(coefficients.begin(), coefficients.end(), [](double k) { return k != 0; })) {
    diagnostics.warning(where +
                        " <distortion> is not applied: bullet_sim renders an undistorted pinhole image");
  }
  return coefficients;
}

/// The <camera> block of the sensor: field of view, image, clip planes and noise.
std::array<double, 5> readCameraTags(const TagNode* sensor, const std::string& where,
                                     PinholeCameraConfig& config, Diagnostics& diagnostics) {
  const TagNode* camera = sensor ? sensor->child("camera") : nullptr;
  PluginTags tags(camera, where + " <camera>", diagnostics);
  config.horizontal_fov = tags.positive("horizontal_fov", config.horizontal_fov);
  if (config.horizontal_fov >= M_PI) {
    diagnostics.error(where + " <horizontal_fov> [" + std::to_string(config.horizontal_fov) +
                      "] must be below pi rad for a pinhole camera");
  }
  tags.accept({"image", "clip", "noise", "distortion", "lens", "save", "depth_camera"});
  tags.finish();
  readImageTags(camera, where, config, diagnostics);

  PluginTags clip(camera ? camera->child("clip") : nullptr, where + " <clip>", diagnostics);
  config.near_clip = clip.positive("near", config.near_clip);
  config.far_clip = clip.positive("far", config.far_clip);
  clip.finish();
  if (config.far_clip <= config.near_clip) {
    diagnostics.error(where + " <clip> <far> [" + std::to_string(config.far_clip) + "] must exceed <near> [" +
                      std::to_string(config.near_clip) + "]");
  }

  if (const TagNode* noise_node = camera ? camera->child("noise") : nullptr) {
    PluginTags noise(noise_node, where + " <noise>", diagnostics);
    const std::string type = noise.text("type", "gaussian");
    if (type != "gaussian" && type != "none")
      diagnostics.error(where + " <noise><type> must be gaussian or none, not [" + type + "]");
    config.noise_mean = type == "none" ? 0 : noise.number("mean", 0);
    config.noise_stddev = type == "none" ? 0 : noise.deviation("stddev", 0);
    noise.finish();
  }
  return readDistortion(camera, where, diagnostics);
}

/// gazebo_ros_camera_utils' tags: names, intrinsics and distortion (the registry reads the rate).
void readCameraPluginTags(PluginTags& tags, const std::array<double, 5>& sdf_distortion,
                          PinholeCameraConfig& config) {
  config.camera_name = tags.text("cameraName");
  config.image_topic = tags.text("imageTopicName");
  config.info_topic = tags.text("cameraInfoTopicName");
  config.frame = tags.frame("frameName", config.link);
  config.hack_baseline = tags.number("hackBaseline");
  config.focal_length = tags.nonNegative("focalLength");
  config.cx = tags.number("Cx");
  config.cy = tags.number("Cy");
  const char* names[] = {"distortionK1", "distortionK2", "distortionT1", "distortionT2", "distortionK3"};
  for (size_t i = 0; i < config.distortion.size(); ++i) config.distortion[i] = tags.number(names[i]);
  if (tags.flag("autoDistortion")) config.distortion = sdf_distortion;
}

/// Whether the <sensor>'s <update_rate> is written below 0: its own warning says it is 0, every step.
bool rateWrittenNegative(const TagNode* sensor) {
  const TagNode* rate = sensor ? sensor->child("update_rate") : nullptr;
  return rate && std::strtod(rate->text.c_str(), nullptr) < 0;
}

void checkCamera(const DeclarationSource& source, const PinholeCameraConfig& config) {
  const std::string where = source.declaration.where();
  if (config.update_rate == 0 && !rateWrittenNegative(source.sensor)) {
    source.diagnostics.warning(
        where + " has update_rate 0 (Gazebo renders it as often as it can): it renders every step");
  }
  if (config.focal_length > 0 && std::abs(config.focal_length - config.renderedFocalLength()) > 1e-6) {
    source.diagnostics.warning(where + " <focalLength> [" + std::to_string(config.focal_length) +
                               "] differs from width / (2 tan(fov / 2)) = " +
                               std::to_string(config.renderedFocalLength()) +
                               ": camera_info carries the given one, the image is rendered with the other");
  }
  frameLink(source, "frameName", config.frame);
}

void parseAnyCamera(const DeclarationSource& source, bool depth, PinholeCameraConfig& config) {
  const SensorDeclaration& sensor = *source.declaration.sensor;
  const std::string where = source.declaration.where();
  config.depth = depth;
  if (sensor.type == "wideanglecamera") {
    source.diagnostics.warning(where + " is a wide-angle camera: bullet_sim draws it as a pinhole camera "
                                       "of the same <horizontal_fov>, without its <lens> projection");
  }
  const auto sdf_distortion = readCameraTags(source.sensor, where, config, source.diagnostics);
  if (static_cast<double>(config.width) * config.height > source.limits.max_image_pixels) {
    source.diagnostics.error(where + " <image> of " + std::to_string(config.width) + " x " +
                             std::to_string(config.height) + " px is above the limit of " +
                             std::to_string(source.limits.max_image_pixels) + " pixels (max_image_pixels)");
  }
  readCameraPluginTags(source.tags, sdf_distortion, config);
  checkCamera(source, config);
}

}  // namespace

double PinholeCameraConfig::renderedFocalLength() const { return width / (2 * std::tan(horizontal_fov / 2)); }

CameraInfo PinholeCameraConfig::info() const {
  CameraInfo info;
  info.frame_id = frame;
  info.camera_name = camera_name;
  info.width = width;
  info.height = height;
  const double f = focal_length > 0 ? focal_length : renderedFocalLength();
  const double centre_x = cx != 0 ? cx : (width + 1.0) / 2;
  const double centre_y = cy != 0 ? cy : (height + 1.0) / 2;
  info.D = distortion;
  info.K = {f, 0, centre_x, 0, f, centre_y, 0, 0, 1};
  info.P = {f, 0, centre_x, -f * hack_baseline, 0, f, centre_y, 0, 0, 0, 1, 0};
  return info;
}

void parseCamera(const DeclarationSource& source, PinholeCameraConfig& config) {
  parseAnyCamera(source, false, config);
}

void parseDepthCamera(const DeclarationSource& source, PinholeCameraConfig& config) {
  parseAnyCamera(source, true, config);
  PluginTags& tags = source.tags;
  config.depth_topic = tags.text("depthImageTopicName");
  config.depth_info_topic = tags.text("depthImageCameraInfoTopicName");
  config.points_topic = tags.text("pointCloudTopicName");
  config.cloud_cutoff = tags.nonNegative("pointCloudCutoff");
  config.cloud_cutoff_max = tags.positive("pointCloudCutoffMax");
  config.depth_16uc1 = tags.flag("useDepth16UC1Format");
  if (config.cloud_cutoff_max <= config.cloud_cutoff) {
    source.diagnostics.error(source.declaration.where() + " <pointCloudCutoffMax> [" +
                             std::to_string(config.cloud_cutoff_max) + "] must exceed <pointCloudCutoff> [" +
                             std::to_string(config.cloud_cutoff) + "]");
  }
}

PinholeCamera::PinholeCamera(const PluginDeclaration& declaration, const PinholeCameraConfig& config,
                             const PluginSetup& setup)
    : Plugin(declaration, setup), config_(config), images_(setup.images) {
  info_.next() = depth_info_.next() = config_.info();
  image_.next().frame_id = depth_.next().frame_id = cloud_.next().frame_id = config_.frame;
  addOutput(underCamera(config_.camera_name, config_.image_topic), image_, &image_demand_);
  addOutput(underCamera(config_.camera_name, config_.info_topic), info_);
  if (!config_.depth) return;
  addOutput(underCamera(config_.camera_name, config_.depth_topic), depth_, &depth_demand_);
  addOutput(underCamera(config_.camera_name, config_.depth_info_topic), depth_info_);
  addOutput(underCamera(config_.camera_name, config_.points_topic), cloud_, &cloud_demand_);
}

ImageRequest PinholeCamera::imageRequest(const RobotBody& body, bool depth) const {
  ImageRequest request;
  request.pose = body.linkPose(config_.link) * config_.pose;
  request.width = config_.width;
  request.height = config_.height;
  request.horizontal_fov = config_.horizontal_fov;
  request.near_clip = config_.near_clip;
  request.far_clip = config_.far_clip;
  request.depth = depth;
  return request;
}

void PinholeCamera::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer().due(time)) return;  // frames stay on the update grid whether or not anyone listens
  const bool want_depth = config_.depth && (depth_demand_.wanted || cloud_demand_.wanted);
  if (!images_ || !(image_demand_.wanted || want_depth)) return;
  images_->render(imageRequest(body, want_depth), frame_);
  addNoise(frame_);
  publishImage(frame_, time.sim_time);
  if (!want_depth) return;
  publishDepth(frame_, time.sim_time);
  if (cloud_demand_.wanted) publishCloud(frame_, time.sim_time);
}

void PinholeCamera::addNoise(RenderedImage& rendered) {
  if (config_.noise_stddev <= 0 && config_.noise_mean == 0) return;
  std::normal_distribution<double> gaussian(config_.noise_mean * 255, config_.noise_stddev * 255);
  for (size_t pixel = 0; pixel < rendered.rgb.size(); pixel += 3) {
    const double offset = gaussian(noise());  // one draw per pixel, on every channel, as Gazebo's shader
    for (size_t c = pixel; c < pixel + 3; ++c)
      rendered.rgb[c] = static_cast<uint8_t>(std::clamp(std::lround(rendered.rgb[c] + offset), 0L, 255L));
  }
}

namespace {

/// Writes RGB pixels as `channels` values (3: in `order`, 1: luminance) of `Value`, each 8-bit value scaled
/// by `scale` (257 spreads it over 16 bits).
template <class Value>
void convertPixels(const uint8_t* rgb, size_t pixels, int channels, const std::array<int, 3>& order,
                   Value scale, uint8_t* out) {
  for (size_t p = 0; p < pixels; ++p, rgb += 3) {
    Value values[3];
    if (channels == 1) {
      values[0] = static_cast<Value>(std::lround(0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2]) * scale);
    } else {
      for (int c = 0; c < 3; ++c) values[c] = static_cast<Value>(rgb[order[c]] * scale);
    }
    std::memcpy(out, values, channels * sizeof(Value));
    out += channels * sizeof(Value);
  }
}

}  // namespace

void PinholeCamera::publishImage(const RenderedImage& rendered, double stamp) {
  CameraImage& image = image_.next();
  image.stamp = stamp;
  image.width = rendered.width;
  image.height = rendered.height;
  image.encoding = config_.encoding;
  const bool mono = image.encoding.rfind("mono", 0) == 0;
  const bool wide = image.encoding.back() == '6';  // rgb16, mono16
  const size_t pixels = rendered.rgb.size() / 3;
  const int channels = mono ? 1 : 3, bytes = wide ? 2 : 1;
  image.step = rendered.width * channels * bytes;
  image.data.resize(pixels * channels * bytes);
  const std::array<int, 3> order = image.encoding == "bgr8" ? std::array{2, 1, 0} : std::array{0, 1, 2};
  if (image.encoding == "rgb8") {
    std::memcpy(image.data.data(), rendered.rgb.data(), rendered.rgb.size());
  } else if (wide) {
    convertPixels<uint16_t>(rendered.rgb.data(), pixels, channels, order, 257, image.data.data());
  } else {
    convertPixels<uint8_t>(rendered.rgb.data(), pixels, channels, order, 1, image.data.data());
  }
  image_.publish();
  info_.next().stamp = stamp;
  info_.publish();
}

void PinholeCamera::publishDepth(const RenderedImage& rendered, double stamp) {
  CameraImage& image = depth_.next();
  image.stamp = stamp;
  image.width = rendered.width;
  image.height = rendered.height;
  image.encoding = config_.depth_16uc1 ? "16UC1" : "32FC1";
  const size_t bytes = config_.depth_16uc1 ? 2 : 4;
  image.step = static_cast<int>(rendered.width * bytes);
  image.data.resize(rendered.depth.size() * bytes);
  uint8_t* out = image.data.data();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  if (config_.depth_16uc1) {
    for (const float depth : rendered.depth) {
      const uint16_t millimetres =
          config_.withinCutoffs(depth) ? static_cast<uint16_t>(std::lround(depth * 1000)) : 0;
      std::memcpy(out, &millimetres, 2);
      out += 2;
    }
  } else {
    for (const float depth : rendered.depth) {
      const float metres = config_.withinCutoffs(depth) ? depth : nan;
      std::memcpy(out, &metres, 4);
      out += 4;
    }
  }
  depth_.publish();
  depth_info_.next().stamp = stamp;
  depth_info_.publish();
}

void PinholeCamera::publishCloud(const RenderedImage& rendered, double stamp) {
  ColouredCloud& cloud = cloud_.next();
  cloud.stamp = stamp;
  cloud.width = rendered.width;
  cloud.height = rendered.height;
  cloud.points.resize(rendered.depth.size());
  cloud.rgb.resize(rendered.depth.size());
  static_assert(sizeof(cloud.rgb[0]) == 3, "the cloud's colours are packed as the image's");
  std::memcpy(cloud.rgb.data(), rendered.rgb.data(), rendered.rgb.size());
  // As gazebo_ros_openni_kinect: rays through pixel centres, column i at (i - (width - 1) / 2) / f.
  const double f = config_.renderedFocalLength();
  const double centre_x = 0.5 * (rendered.width - 1), centre_y = 0.5 * (rendered.height - 1);
  ray_x_.resize(rendered.width);
  for (int column = 0; column < rendered.width; ++column) {
    ray_x_[column] = static_cast<float>((column - centre_x) / f);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  size_t seen = 0;
  for (int row = 0; row < rendered.height; ++row) {
    const auto ray_y = static_cast<float>((row - centre_y) / f);
    const size_t first = static_cast<size_t>(row) * rendered.width;
    for (int column = 0; column < rendered.width; ++column) {
      const float depth = rendered.depth[first + column];
      const bool within = config_.withinCutoffs(depth);
      seen += within;
      cloud.points[first + column] = within ? Eigen::Vector3f(depth * ray_x_[column], depth * ray_y, depth)
                                            : Eigen::Vector3f(nan, nan, nan);
    }
  }
  cloud.is_dense = seen == cloud.points.size();
  cloud_.publish();
}

namespace {

/// gazebo_ros_camera_utils' tags, which every camera plugin reads; a depth camera's image is its infrared
/// one.
TagTable cameraTags(bool depth) {
  const std::string image = depth ? "ir/image_raw" : "image_raw";
  const std::string info = depth ? "ir/camera_info" : "camera_info";
  return {
      {"cameraName", TagType::kText, "", "",
       "the namespace of its topics inside the plugin's, and camera_info's camera_name", ""},
      {"imageTopicName", TagType::kTopic, image, "", "the topic of the image", ""},
      {"cameraInfoTopicName", TagType::kTopic, info, "", "the topic of the image's camera_info", ""},
      {"frameName", TagType::kFrame, "the sensor's link", "", "the messages' frame_id; empty when absent",
       "the sensor's link when absent; a name that is no link is a warning, and is still the frame_id"},
      {"updateRate", TagType::kRate, "0", "Hz",
       "throttles the plugin below the sensor's <update_rate>; 0: every frame the sensor renders", ""},
      {"focalLength", TagType::kPositive, "0", "px",
       "camera_info's focal length; 0: width / (2 tan(horizontal_fov / 2)); another value is a warning",
       "the same; the image is rendered from <horizontal_fov> whatever it says"},
      {"Cx", TagType::kNumber, "0", "px", "camera_info's principal point x; 0: (width + 1) / 2", ""},
      {"Cy", TagType::kNumber, "0", "px", "camera_info's principal point y; 0: (height + 1) / 2", ""},
      {"hackBaseline", TagType::kNumber, "0", "m",
       "a stereo pair's baseline: camera_info's P[3] = -focal length x it", ""},
      {"distortionK1", TagType::kNumber, "0", "", "camera_info's D[0]; the image is not distorted by it", ""},
      {"distortionK2", TagType::kNumber, "0", "", "camera_info's D[1]; the image is not distorted by it", ""},
      {"distortionT1", TagType::kNumber, "0", "", "camera_info's D[2]; the image is not distorted by it", ""},
      {"distortionT2", TagType::kNumber, "0", "", "camera_info's D[3]; the image is not distorted by it", ""},
      {"distortionK3", TagType::kNumber, "0", "", "camera_info's D[4]; the image is not distorted by it", ""},
      {"autoDistortion", TagType::kFlag, "false", "",
       "true: camera_info's D from the sensor's <distortion> instead of the five tags above", ""},
      {"CxPrime", TagType::kIgnored, "", "px", "read, and in no message", ""},
      {"borderCrop", TagType::kIgnored, "", "",
       "whether the distorted image is cropped to hide its black border; true when absent",
       "no distortion is rendered, so there is nothing to crop"},
      {"triggerTopicName", TagType::kIgnored, "", "",
       "read; only the triggered camera plugins subscribe to it", ""},
      {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
  };
}

/// A depth camera plugin's tags: gazebo_ros_camera_utils' and the depth image's, the cloud's and their
/// cut-offs.
TagTable depthCameraTags(bool openni) {
  TagTable table = cameraTags(/*depth=*/true);
  const std::string not_read = "not read (libgazebo_ros_depth_camera.so's tag)";
  const std::string not_ours = "no such cloud is published";
  const std::vector<TagRow> rows = {
      {"depthImageTopicName", TagType::kTopic, "depth/image_raw", "", "the topic of the depth image", ""},
      {"depthImageCameraInfoTopicName", TagType::kTopic, "depth/camera_info", "",
       "the topic of the depth image's camera_info", ""},
      {"pointCloudTopicName", TagType::kTopic, "points", "", "the topic of the organized point cloud", ""},
      {"pointCloudCutoff", TagType::kPositive, "0.4", "m",
       "depths at or below it are NaN in the cloud and the depth image (0 in 16UC1)", ""},
      {"pointCloudCutoffMax", TagType::kPositive, "5", "m",
       openni ? "depths at or beyond it are NaN in the cloud and the depth image (0 in 16UC1)"
              : "not read: libgazebo_ros_depth_camera.so keeps every depth beyond pointCloudCutoff",
       openni ? "" : "read as libgazebo_ros_openni_kinect.so reads it"},
      {"useDepth16UC1Format", TagType::kFlag, "false", "",
       "true: the depth image in 16UC1 millimetres, else 32FC1 metres", ""},
      {"reflectanceTopicName", TagType::kIgnored, "", "",
       openni ? not_read : "the topic of a reflectance cloud; reflectance when absent",
       openni ? "" : not_ours},
      {"normalsTopicName", TagType::kIgnored, "", "",
       openni ? not_read : "the topic of a cloud of normals; normals when absent", openni ? "" : not_ours},
      {"reduceNormals", TagType::kIgnored, "", "",
       openni ? not_read : "publishes every n-th normal; 50 when absent", openni ? "" : not_ours},
  };
  for (const TagRow& row : rows) table.add(row);
  return table;
}

}  // namespace

BULLET_SIM_PLUGIN_FOLDER(pinhole_camera) {
  const auto add = [&](const char* filename, std::vector<std::string> sensor_types,
                       void (*parse)(const DeclarationSource&, PinholeCameraConfig&), TagTable tags) {
    PluginType type = pluginType<PinholeCamera>(filename, parse, std::move(tags));
    type.sensor_types = std::move(sensor_types);
    // The plugin publishes a frame when its period has passed since the last: the slower rate wins.
    type.rate = {RateRule::From::kSlowerOfSensorAndTags, {"updateRate"}, 0};
    type.needs = kNeedImages;
    registrar.add(std::move(type));
  };
  add("libgazebo_ros_camera.so", {"camera", "wideanglecamera"}, parseCamera, cameraTags(/*depth=*/false));
  add("libgazebo_ros_openni_kinect.so", {"depth"}, parseDepthCamera, depthCameraTags(/*openni=*/true));
  add("libgazebo_ros_depth_camera.so", {"depth"}, parseDepthCamera, depthCameraTags(/*openni=*/false));
}

}  // namespace bullet_sim
