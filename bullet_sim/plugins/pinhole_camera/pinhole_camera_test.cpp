// Cameras against the pinhole model: a depth camera in test_room.world facing the east wall, whose inner face
// is at x = 3.0 m, and a red box of known size and place.
#include <gmock/gmock.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "plugins/pinhole_camera/pinhole_camera.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/simulation_images.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
using test::Tags;

constexpr double kCameraX = 0.1, kCameraZ = 0.45;  // in the world, once the 0.1 m base rests on the floor
constexpr double kWallX = 3.0;
constexpr double kFov = 1.047;
constexpr char kDepthTopic[] = "cam/depth/image_raw";  // the depth image's, with cameraName cam

struct CameraSetup {
  int width = 161, height = 121;
  double rate = 20;
  std::string filename = "libgazebo_ros_openni_kinect.so";
  std::string sensor_type = "depth";
  std::string noise;  ///< the <noise> block, if any
  Tags plugin_tags = {{"cameraName", "cam"}, {"frameName", "base_link"}};
};

/// A 0.2 x 0.2 x 0.1 m box whose camera looks along +x from 0.05 m ahead of its centre, 0.4 m up.
std::string cameraRobot(const CameraSetup& setup) {
  std::string plugin_tags;
  for (const auto& [tag, text] : setup.plugin_tags) plugin_tags += "<" + tag + ">" + text + "</" + tag + ">";
  return R"(<robot name="camera_box">
  <link name="base_link">
    <inertial><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
    <visual><geometry><box size="0.2 0.2 0.1"/></geometry></visual>
  </link>
  <gazebo reference="base_link">
    <sensor type=")" + setup.sensor_type + R"(" name="cam_sensor">
      <pose>0.1 0 0.4 0 0 0</pose>
      <update_rate>)" + std::to_string(setup.rate) + R"(</update_rate>
      <camera>
        <horizontal_fov>)" + std::to_string(kFov) + R"(</horizontal_fov>
        <image><width>)" + std::to_string(setup.width) + "</width><height>" + std::to_string(setup.height) +
         R"(</height><format>R8G8B8</format></image>
        <clip><near>0.05</near><far>10</far></clip>)" + setup.noise + R"(
      </camera>
      <plugin name="cam_plugin" filename=")" + setup.filename + R"(">)" + plugin_tags + R"(</plugin>
    </sensor>
  </gazebo>
</robot>)";
}

/// A red 0.2 m cube, to be seen.
const char* kRedCube = R"(<robot name="red_cube">
  <link name="cube">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
    <visual><geometry><box size="0.2 0.2 0.2"/></geometry>
      <material name="red"><color rgba="1 0 0 1"/></material></visual>
  </link>
</robot>)";

/// Counts renders, drawing with a real OffscreenRenderer.
class CountingRenderer final : public SceneRenderer {
 public:
  Image render(const Scene& scene, int width, int height, std::vector<float>* depth) override {
    ++renders;
    return renderer.render(scene, width, height, depth);
  }
  OffscreenRenderer renderer;
  int renders = 0;
};

struct CameraWorld {
  explicit CameraWorld(const CameraSetup& setup = {}, uint64_t seed = 0) {
    SimulationOptions options;
    options.seed = seed;
    options.images = imagesFrom([this]() -> SceneRenderer& { return renderer; });
    simulation = std::make_unique<Simulation>(test::shippedWorld("test_room.world"), options);
    Robot& robot = simulation->spawn("camera_box", test::parseQuietly(cameraRobot(setup), "camera_box"), {});
    camera = test::pluginsOf<PinholeCamera>(robot).at(0);
  }
  /// Steps until the camera has rendered `frames` more frames, for at most 1 s of sim time.
  void frames(uint64_t frames = 1) {
    const uint64_t target = test::countOf<CameraImage>(*camera) + frames;
    test::stepUntil(
        *simulation, [&] { return test::countOf<CameraImage>(*camera) >= target; }, 1.0, "a camera frame");
  }
  float depthAt(int column, int row) const {
    const CameraImage& depth = test::latestOf<CameraImage>(*camera, kDepthTopic);
    float value;
    std::memcpy(&value, &depth.data[(static_cast<size_t>(row) * depth.width + column) * 4], 4);
    return value;
  }

  CountingRenderer renderer;
  std::unique_ptr<Simulation> simulation;
  PinholeCamera* camera = nullptr;
};

/// Where a point in the world (x ahead of the camera, y to its left, z up) lands: continuous (column, row)
/// from the image's top-left corner, by the pinhole model with square pixels.
Eigen::Vector2d pinhole(const Eigen::Vector3d& point, int width, int height) {
  const double focal = width / (2 * std::tan(kFov / 2));
  const Eigen::Vector3d seen = point - Eigen::Vector3d(kCameraX, 0, kCameraZ);
  return {width / 2.0 - focal * seen.y() / seen.x(), height / 2.0 - focal * seen.z() / seen.x()};
}

TEST(Camera, DepthAtTheImageCentreIsTheDistanceToTheWall) {
  CameraWorld world;
  world.frames();
  const CameraImage& depth = test::latestOf<CameraImage>(*world.camera, kDepthTopic);
  ASSERT_EQ(depth.encoding, "32FC1");
  ASSERT_EQ(depth.width, 161);
  EXPECT_NEAR(world.depthAt(80, 60), kWallX - kCameraX, 0.01);
}

TEST(Camera, OrganizedCloudCentreIsOnTheOpticalAxis) {
  CameraWorld world;
  world.frames();
  const ColouredCloud& cloud = test::latestOf<ColouredCloud>(*world.camera);
  ASSERT_EQ(cloud.width, 161);
  ASSERT_EQ(cloud.height, 121);
  const Eigen::Vector3f centre = cloud.points[60 * 161 + 80];
  EXPECT_NEAR(centre.x(), 0, 1e-4);
  EXPECT_NEAR(centre.y(), 0, 1e-4);
  EXPECT_NEAR(centre.z(), kWallX - kCameraX, 0.01);
  // One column right and one row down: x right and y down, at depth / focal length per pixel.
  const double focal = 161 / (2 * std::tan(kFov / 2));
  const Eigen::Vector3f next = cloud.points[61 * 161 + 81];
  EXPECT_NEAR(next.x(), next.z() / focal, 1e-4);
  EXPECT_NEAR(next.y(), next.z() / focal, 1e-4);
}

TEST(Camera, DepthsOutsideTheCutOffsAreNaNInTheImageAndTheCloud) {
  for (const Tags& cutoffs : {Tags{{"pointCloudCutoffMax", "2.5"}}, Tags{{"pointCloudCutoff", "3.0"}}}) {
    CameraSetup setup;
    setup.plugin_tags.insert(setup.plugin_tags.end(), cutoffs.begin(), cutoffs.end());
    CameraWorld world(setup);
    world.frames();
    EXPECT_TRUE(std::isnan(world.depthAt(80, 60))) << cutoffs[0].first;
    const ColouredCloud& cloud = test::latestOf<ColouredCloud>(*world.camera);
    EXPECT_TRUE(cloud.points[60 * 161 + 80].array().isNaN().all()) << cutoffs[0].first;
    EXPECT_FALSE(cloud.is_dense);
  }
}

TEST(Camera, SixteenBitDepthIsMillimetresAndZeroOutsideTheCutOffs) {
  CameraSetup setup;
  setup.plugin_tags.push_back({"useDepth16UC1Format", "true"});
  CameraWorld world(setup);
  world.frames();
  const CameraImage& depth = test::latestOf<CameraImage>(*world.camera, kDepthTopic);
  ASSERT_EQ(depth.encoding, "16UC1");
  uint16_t centre;
  std::memcpy(&centre, &depth.data[(60 * 161 + 80) * 2], 2);
  EXPECT_NEAR(centre, 1000 * (kWallX - kCameraX), 10);
}

TEST(Camera, ARedCubeAppearsWhereThePinholeModelPutsItsCorners) {
  CameraSetup setup;
  setup.width = 320;
  setup.height = 240;
  CameraWorld world(setup);
  SpawnPose pose;
  pose.x = 2.0;
  pose.y = 0.5;
  world.simulation->spawn("red_cube", test::parseQuietly(kRedCube, "red_cube"), pose);
  world.frames();
  const CameraImage& image = test::latestOf<CameraImage>(*world.camera);
  ASSERT_EQ(image.encoding, "rgb8");
  Eigen::AlignedBox2d red;
  for (int row = 0; row < image.height; ++row) {
    for (int column = 0; column < image.width; ++column) {
      const uint8_t* rgb = &image.data[(static_cast<size_t>(row) * image.width + column) * 3];
      if (rgb[0] > 2 * rgb[1] + 20 && rgb[0] > 2 * rgb[2] + 20) {
        red.extend(Eigen::Vector2d(column, row));
        red.extend(Eigen::Vector2d(column + 1, row + 1));  // pixel (c, r) covers [c, c + 1) x [r, r + 1)
      }
    }
  }
  Eigen::AlignedBox2d predicted;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d point(corner & 1 ? 2.1 : 1.9, corner & 2 ? 0.6 : 0.4, corner & 4 ? 0.2 : 0.0);
    predicted.extend(pinhole(point, image.width, image.height));
  }
  ASSERT_FALSE(red.isEmpty()) << "no red pixel";
  EXPECT_NEAR(red.min().x(), predicted.min().x(), 1);
  EXPECT_NEAR(red.max().x(), predicted.max().x(), 1);
  EXPECT_NEAR(red.min().y(), predicted.min().y(), 1);
  EXPECT_NEAR(red.max().y(), predicted.max().y(), 1);
}

TEST(Camera, CameraInfoFollowsTheFieldOfViewAsGazeboComputesIt) {
  CameraWorld world;
  world.frames();
  const CameraInfo& info = test::latestOf<CameraInfo>(*world.camera);
  const double focal = 161 / (2 * std::tan(kFov / 2));
  EXPECT_NEAR(info.K[0], focal, 1e-9);
  EXPECT_NEAR(info.K[4], focal, 1e-9);
  EXPECT_DOUBLE_EQ(info.K[2], (161 + 1) / 2.0);
  EXPECT_DOUBLE_EQ(info.K[5], (121 + 1) / 2.0);
  EXPECT_DOUBLE_EQ(info.P[0], info.K[0]);
  EXPECT_DOUBLE_EQ(info.P[3], 0);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  EXPECT_EQ(info.stamp, test::latestOf<CameraImage>(*world.camera).stamp);
  EXPECT_EQ(info.frame_id, "base_link");
}

TEST(Camera, TopicsFollowGazeboNamesAndDefaults) {
  CameraWorld world;
  std::vector<std::string> topics;
  for (const OutputPort& port : world.camera->ports().outputs) topics.push_back(port.topic);
  EXPECT_THAT(topics, ::testing::ElementsAre("cam/ir/image_raw", "cam/ir/camera_info", "cam/depth/image_raw",
                                             "cam/depth/camera_info", "cam/points"));
}

TEST(Camera, FramesComeAtTheUpdateRateInSimTime) {
  CameraWorld world;
  std::vector<double> stamps;
  while (world.simulation->time() < 1.0 - 1e-9) {
    world.simulation->step();
    if (test::countOf<CameraImage>(*world.camera) > stamps.size())
      stamps.push_back(test::latestOf<CameraImage>(*world.camera).stamp);
  }
  EXPECT_NEAR(static_cast<double>(stamps.size()), 20, 1);
  for (size_t i = 0; i < stamps.size(); ++i) EXPECT_NEAR(stamps[i], 0.05 * (i + 1), 1e-9);
}

TEST(Camera, NothingIsRenderedWhileNobodyWantsAnImage) {
  CameraWorld world;
  for (const OutputPort& port : world.camera->ports().outputs) {
    if (port.demand) port.demand->wanted = false;
  }
  for (int step = 0; step < 500; ++step) world.simulation->step();
  EXPECT_EQ(world.renderer.renders, 0);
  EXPECT_EQ(test::countOf<CameraImage>(*world.camera), 0u);
  world.camera->ports().outputs.front().demand->wanted = true;  // someone subscribes to the image
  world.frames();
  EXPECT_EQ(world.renderer.renders, 1);
}

TEST(Camera, TheSameSeedGivesTheSameNoisyImages) {
  CameraSetup setup;
  setup.noise = "<noise><type>gaussian</type><mean>0</mean><stddev>0.05</stddev></noise>";
  CameraWorld first(setup, 7), second(setup, 7), other(setup, 8);
  first.frames(2);
  second.frames(2);
  other.frames(2);
  EXPECT_EQ(test::latestOf<CameraImage>(*first.camera).data,
            test::latestOf<CameraImage>(*second.camera).data);
  EXPECT_NE(test::latestOf<CameraImage>(*first.camera).data, test::latestOf<CameraImage>(*other.camera).data);
}

TEST(Camera, ANegativeNoiseStddevIsReadAsItsAbsoluteValue) {
  // Gazebo's noise adds stddev times a standard normal, which the sign does not change.
  CameraSetup setup;
  setup.noise = "<noise><type>gaussian</type><mean>0</mean><stddev>-0.05</stddev></noise>";
  std::vector<std::string> warnings;
  const ModelSpec model =
      parseModel(cameraRobot(setup), "camera_box", PackageResolver::fromEnvironment(), &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("<noise> <stddev> -0.05 is negative: read as 0.05, as Gazebo's Gaussian "
                                     "noise takes it"));
  EXPECT_EQ(model.plugins.at(0).configAs<PinholeCameraConfig>()->noise_stddev, 0.05);
}

TEST(Camera, ANegativeUpdateRateGetsOneWarningAndRendersEveryStep) {
  const auto warningsAt = [](double rate) {
    CameraSetup setup;
    setup.rate = rate;
    std::vector<std::string> warnings;
    parseModel(cameraRobot(setup), "camera_box", PackageResolver::fromEnvironment(), &warnings);
    return warnings;
  };
  EXPECT_THAT(warningsAt(-1), testing::ElementsAre(HasSubstr("<update_rate> -1 is below 0: read as 0, every "
                                                             "step, as Gazebo does")));
  EXPECT_THAT(warningsAt(0), testing::ElementsAre(HasSubstr("has update_rate 0 (Gazebo renders it as often "
                                                            "as it can): it renders every step")));
  CameraSetup setup;
  setup.rate = -1;
  CountingRenderer renderer;
  SimulationOptions options;
  options.images = imagesFrom([&]() -> SceneRenderer& { return renderer; });
  Simulation simulation(test::shippedWorld("test_room.world"), options);
  std::vector<std::string> warnings;
  ModelSpec model =
      parseModel(cameraRobot(setup), "camera_box", PackageResolver::fromEnvironment(), &warnings);
  const PinholeCamera& camera =
      *test::pluginsOf<PinholeCamera>(simulation.spawn("camera_box", std::move(model), {})).at(0);
  for (int step = 0; step < 10; ++step) simulation.step();
  EXPECT_EQ(test::countOf<CameraImage>(camera, kDepthTopic), 10u) << "a frame every step";
}

TEST(Camera, ColourFormatsMapToTheirRosEncodings) {
  for (const auto& [format, encoding] : std::vector<std::pair<std::string, std::string>>{
           {"B8G8R8", "bgr8"}, {"L8", "mono8"}, {"R16G16B16", "rgb16"}}) {
    CameraSetup setup;
    setup.filename = "libgazebo_ros_camera.so";
    setup.sensor_type = "camera";
    std::string urdf = cameraRobot(setup);
    urdf.replace(urdf.find("R8G8B8"), 6, format);
    SimulationOptions options;
    CountingRenderer renderer;
    options.images = imagesFrom([&]() -> SceneRenderer& { return renderer; });
    Simulation simulation(test::shippedWorld("test_room.world"), options);
    auto* camera =
        test::pluginsOf<PinholeCamera>(simulation.spawn("box", test::parseQuietly(urdf, format), {})).at(0);
    test::stepUntil(simulation, [&] { return test::countOf<CameraImage>(*camera) > 0; }, 1.0, format);
    const CameraImage& image = test::latestOf<CameraImage>(*camera);
    EXPECT_EQ(image.encoding, encoding);
    const int bytes = encoding == "mono8" ? 1 : encoding == "rgb16" ? 6 : 3;
    EXPECT_EQ(image.step, 161 * bytes);
    EXPECT_EQ(image.data.size(), 161u * 121 * bytes);
  }
}

TEST(Camera, WithoutARendererACameraRendersNothing) {
  Simulation simulation(test::shippedWorld("test_room.world"));
  const auto* camera =
      test::pluginsOf<PinholeCamera>(
          simulation.spawn("camera_box", test::parseQuietly(cameraRobot({}), "camera_box"), {}))
          .at(0);
  for (int step = 0; step < 200; ++step) simulation.step();
  EXPECT_EQ(test::countOf<CameraImage>(*camera), 0u);
}

TEST(Camera, BadCameraTagsAreReportedWithTheirValues) {
  std::string urdf = cameraRobot({});
  urdf.replace(urdf.find("R8G8B8"), 6, "BAYER_RGGB8");
  std::vector<std::string> warnings;
  parseModel(urdf, "bayer_camera", PackageResolver::fromEnvironment(), &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("<format> [BAYER_RGGB8] is not simulated"));

  urdf.replace(urdf.find("<far>10</far>"), 13, "<far>0.01</far>");
  try {
    parseModel(urdf, "bad_clip", PackageResolver::fromEnvironment());
    FAIL() << "a far clip below the near clip must be refused";
  } catch (const SpecError& error) {
    EXPECT_THAT(error.what(), HasSubstr("<clip> <far> [0.010000] must exceed <near> [0.050000]"));
  }
}

}  // namespace
}  // namespace bullet_sim
