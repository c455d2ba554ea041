// The headless renderer against analytic pictures: walls where the orthographic projection puts them, lidar
// hits where the beams end, the right way up and round; PNG round trips; every shipped robot through the code
// render_model runs, and render_model itself. In-process, no roscore, no display.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <functional>

#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/render/image.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/recording.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "bullet_sim/scene/scene_builder.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

constexpr int kWidth = 640, kHeight = 480;
constexpr int kColourTolerance = 2;  // [0, 255] per channel: OpenGL's rounding of lit colours

Eigen::Vector3i rgbAt(const Image& image, int column, int row) {
  const auto pixel = image.at(column, row);
  return Eigen::Vector3i(pixel[0], pixel[1], pixel[2]);
}

Eigen::Vector3i bytes(const Eigen::Vector3d& colour) { return (colour * 255).array().round().cast<int>(); }

bool sameColour(const Eigen::Vector3i& actual, const Eigen::Vector3i& expected) {
  return (actual - expected).cwiseAbs().maxCoeff() <= kColourTolerance;
}

std::string text(const Eigen::Vector3i& rgb) {
  return "(" + std::to_string(rgb[0]) + ", " + std::to_string(rgb[1]) + ", " + std::to_string(rgb[2]) + ")";
}

/// Pixels for which `test(column, row)` holds.
int countPixels(const Image& image, const std::function<bool(int, int)>& test) {
  int count = 0;
  for (int row = 0; row < image.height; ++row) {
    for (int column = 0; column < image.width; ++column) count += test(column, row);
  }
  return count;
}

/// The pixel a point lands in.
Eigen::Vector2i pixelOf(const Camera& camera, const Eigen::Vector3d& point, int width, int height) {
  const auto projected = camera.project(point, width, height);
  EXPECT_TRUE(projected) << "behind the camera: " << point.transpose();
  return projected ? Eigen::Vector2i(std::floor(projected->x()), std::floor(projected->y()))
                   : Eigen::Vector2i(-1, -1);
}

SceneMesh box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre, const Eigen::Vector4d& rgba) {
  Shape shape;
  shape.box_size = size;
  return {tessellate(shape), Eigen::Isometry3d(Eigen::Translation3d(centre)), rgba};
}

/// A scene of bare meshes: no ground grid, and a background that no lit mesh produces.
Scene bareScene() {
  Scene scene;
  scene.ground_grid = false;
  scene.background = Eigen::Vector4d(1, 0, 1, 1);
  return scene;
}

bool isBackground(const Image& image, int column, int row) {
  return sameColour(rgbAt(image, column, row), Eigen::Vector3i(255, 0, 255));
}

ModelSpec lidarMast() {
  return parseModel(test::readFile(test::fixture("robots/lidar_mast.urdf")), "lidar_mast.urdf",
                    PackageResolver::fromEnvironment());
}

Image readPng(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    ADD_FAILURE() << "cannot read [" << path << "]: " << png.message;
    return {};
  }
  png.format = PNG_FORMAT_RGBA;
  Image image{static_cast<int>(png.width), static_cast<int>(png.height),
              std::vector<uint8_t>(PNG_IMAGE_SIZE(png))};
  EXPECT_TRUE(png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) << png.message;
  return image;
}

std::string temporaryPath(const std::string& suffix) {
  char path[] = "/tmp/render_test_XXXXXX";
  const int fd = mkstemp(path);
  close(fd);
  std::remove(path);
  return path + suffix;
}

TEST(Render, WheelchairCoversAPlausibleAreaAroundTheImageCentreInAChaseView) {
  const ModelSpec chair = test::wheelchair();
  Scene scene = bareScene();
  // base_footprint at the origin, every joint at 0: the wheels stand on z = 0.
  const Eigen::AlignedBox3d bounds = addModel(scene, chair, linkPosesAtZero(chair));
  EXPECT_NEAR(bounds.min().z(), 0, 0.01) << "the wheels reach the ground";
  scene.camera = chaseCamera(Eigen::Isometry3d::Identity(), bounds);
  const Image image = OffscreenRenderer().render(scene, kWidth, kHeight);

  double covered = 0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  bool touches_border = false;
  for (int row = 0; row < kHeight; ++row) {
    for (int column = 0; column < kWidth; ++column) {
      if (isBackground(image, column, row)) continue;
      ++covered;
      centroid += Eigen::Vector2d(column + 0.5, row + 0.5);
      touches_border |= row == 0 || column == 0 || row == kHeight - 1 || column == kWidth - 1;
    }
  }
  ASSERT_GT(covered, 0);
  centroid /= covered;
  const double share = covered / (kWidth * kHeight);
  EXPECT_GT(share, 0.02);
  EXPECT_LT(share, 0.25);
  EXPECT_FALSE(touches_border) << "the whole chair is in the picture";
  EXPECT_NEAR(centroid.x(), kWidth / 2.0, 0.1 * kWidth);
  EXPECT_NEAR(centroid.y(), kHeight / 2.0, 0.15 * kHeight);

  // The frame (Gazebo/Gray) and the tyres (Gazebo/Black) both show: lit grey, and black, which the ambient
  // term keeps black.
  const int black = countPixels(image, [&](int c, int r) { return rgbAt(image, c, r).maxCoeff() <= 2; });
  const int grey = countPixels(image, [&](int c, int r) {
    const Eigen::Vector3i rgb = rgbAt(image, c, r);
    return rgb.maxCoeff() - rgb.minCoeff() <= 2 &&
           rgb[0] >= bytes(0.7 * scene.lighting.ambient * Eigen::Vector3d::Ones())[0];
  });
  EXPECT_GT(black, 0.1 * covered) << "tyres";
  EXPECT_GT(grey, 0.3 * covered) << "seat, backrest and frame";
}

TEST(Render, TopViewOfTheTestRoomShowsTheWallsWhereTheOrthographicProjectionPutsThem) {
  Scene scene = bareScene();
  addWorld(scene, test::shippedWorld("test_room.world"));
  // 7 m x 5 m asked for; the 4:3 image then shows 7 m x 5.25 m with square pixels of 7 / 640 m.
  scene.camera = Camera::topDown(Eigen::Vector2d::Zero(), Eigen::Vector2d(3.5, 2.5));
  const Image image = OffscreenRenderer().render(scene, kWidth, kHeight);
  const double metres_per_pixel = 7.0 / kWidth;

  // Every pixel looks at an upward face: the floor (Gazebo/Grey) or a wall top, lit from the same angle.
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3i floor = bytes(scene.lighting.shade({0.7, 0.7, 0.7, 1}, up));
  const Eigen::Vector3i east_west = bytes(scene.lighting.shade({0.8, 0.8, 0.75, 1}, up));
  const Eigen::Vector3i north_south = bytes(scene.lighting.shade({0.7, 0.75, 0.8, 1}, up));
  ASSERT_FALSE(sameColour(floor, east_west) || sameColour(floor, north_south));

  // Inner faces at |x| = 3 and |y| = 2, outer faces 0.1 m further out. Pixels within 1.5 px of an edge may
  // show either side, and so may the corners, where two wall tops overlap at the same height.
  const double margin = 1.5 * metres_per_pixel;
  const auto expected = [&](double x, double y) -> std::optional<Eigen::Vector3i> {
    const auto in_wall = [&](double v, double inner) {
      const double a = std::abs(v);
      if (std::abs(a - inner) < margin || std::abs(a - inner - 0.1) < margin) return -1;  // an edge
      return a > inner && a < inner + 0.1 ? 1 : 0;
    };
    const int in_x = in_wall(x, 3), in_y = in_wall(y, 2);
    if (in_x == 0 && in_y == 0) return floor;  // inside the room, or the ground around it
    if (in_y == 1 && std::abs(x) < 3 - margin) return north_south;
    if (in_x == 1 && std::abs(y) < 2 - margin) return east_west;
    return std::nullopt;
  };
  int walls = 0, floors = 0;
  for (int row = 0; row < kHeight; ++row) {
    for (int column = 0; column < kWidth; ++column) {
      const double x = (column + 0.5 - kWidth / 2.0) * metres_per_pixel;
      const double y = (kHeight / 2.0 - row - 0.5) * metres_per_pixel;  // +y up
      const auto colour = expected(x, y);
      if (!colour) continue;
      const Eigen::Vector3i actual = rgbAt(image, column, row);
      ASSERT_TRUE(sameColour(actual, *colour))
          << "pixel (" << column << ", " << row << ") at x " << x << " y " << y << " is " << text(actual)
          << ", expected " << text(*colour);
      (*colour == floor ? floors : walls) += 1;
    }
  }
  // The walls' 0.1 m width less the edge bands, along 6 m north and south and 4 m east and west.
  const double counted_width = 0.1 - 2 * margin;
  const double wall_pixels = (2 * 6.0 + 2 * 4.0) * counted_width / (metres_per_pixel * metres_per_pixel);
  EXPECT_NEAR(walls, wall_pixels, 0.1 * wall_pixels);
  EXPECT_GT(floors, 0.8 * kWidth * kHeight);
  EXPECT_TRUE(sameColour(rgbAt(image, kWidth / 2, kHeight / 2), floor)) << "floor in the middle";
}

/// A 0.6 x 0.4 x 0.5 m box robot in Gazebo/Grey, the ground's colour.
ModelSpec greyBox() {
  const std::string urdf = R"(<robot name="grey_box"><link name="base_link">
    <inertial><mass value="1.0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <visual><geometry><box size="0.6 0.4 0.5"/></geometry></visual>
    <collision><geometry><box size="0.6 0.4 0.5"/></geometry></collision></link>
    <gazebo reference="base_link"><material>Gazebo/Grey</material></gazebo></robot>)";
  return test::parseQuietly(urdf, "grey_box");
}

TEST(Render, APlanOutlinesARobotTheColourOfTheFloor) {
  // Lit from above, the box's top is the floor's colour: only an outline tells them apart.
  const RobotSnapshot snapshot = snapshotRobot(test::shippedWorld("empty.world"), greyBox(), {}, View::kTop);
  Scene scene = snapshot.scene;
  scene.ground_grid = false;
  const Image image = OffscreenRenderer().render(scene, kWidth, kHeight);
  const Eigen::Vector3i floor = bytes(scene.lighting.shade({0.7, 0.7, 0.7, 1}, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3i outline = bytes(scene.outline_rgba.head<3>());
  const auto at = [&](double x, double y) {
    return pixelOf(scene.camera, Eigen::Vector3d(x, y, 0.5), kWidth, kHeight);
  };
  EXPECT_TRUE(sameColour(rgbAt(image, at(0, 0).x(), at(0, 0).y()), floor)) << "the box top";
  EXPECT_TRUE(sameColour(rgbAt(image, at(0.6, 0).x(), at(0.6, 0).y()), floor)) << "the ground beside it";
  // One pixel beyond each side's middle: the outline.
  for (const Eigen::Vector2i& edge : {at(0.3, 0), at(-0.3, 0), at(0, 0.2), at(0, -0.2)}) {
    const Eigen::Vector2i centre = at(0, 0);
    const Eigen::Vector2i outward = (edge - centre).cwiseSign();
    bool outlined = false;
    for (int step = -1; step <= 2; ++step) {  // within a pixel of the projected edge
      const Eigen::Vector2i pixel = edge + step * outward;
      outlined |= sameColour(rgbAt(image, pixel.x(), pixel.y()), outline);
    }
    EXPECT_TRUE(outlined) << "no outline near pixel " << edge.transpose();
  }
}

TEST(Render, APlanOfTheWheelchairShowsItsSeatAndBackrest) {
  // They are Gazebo/Grey like the ground: the plan showed the wheels and armrests only.
  const RobotSnapshot snapshot =
      snapshotRobot(test::shippedWorld("empty.world"), test::wheelchair(), {}, View::kTop);
  const Image image = OffscreenRenderer().render(snapshot.scene, kWidth, kHeight);
  const ModelSpec chair = test::wheelchair();
  Eigen::AlignedBox3d body;  // base_link's visual, where the chair spawns at rest
  const Eigen::Isometry3d base = Eigen::Translation3d(0, 0, 0.6040562) * Eigen::Isometry3d::Identity();
  for (const Visual& visual : chair.link("base_link")->visuals)
    body.extend(boundingBox(visual.shape, base * visual.origin));
  const Eigen::Vector2i a = pixelOf(snapshot.scene.camera, body.min(), kWidth, kHeight);
  const Eigen::Vector2i b = pixelOf(snapshot.scene.camera, body.max(), kWidth, kHeight);
  const Eigen::Vector3i outline = bytes(snapshot.scene.outline_rgba.head<3>());
  const int outlined = countPixels(image, [&](int column, int row) {
    return column >= std::min(a.x(), b.x()) && column <= std::max(a.x(), b.x()) &&
           row >= std::min(a.y(), b.y()) && row <= std::max(a.y(), b.y()) &&
           sameColour(rgbAt(image, column, row), outline);
  });
  // The seat's and the backrest's edges run about 2 x (0.45 + 0.45) m, at about 100 px per metre.
  EXPECT_GT(outlined, 100);
}

TEST(Render, LidarHitsAreDrawnWhereTheBeamsHit) {
  Simulation simulation(test::shippedWorld("test_room.world"));
  Robot& mast = simulation.spawn("mast", lidarMast(), {});
  const Stream<LaserScan>* lidar = mast.outputs<LaserScan>().at(0).stream;
  ASSERT_TRUE(test::stepUntil(
      simulation, [&] { return lidar->count() > 0; }, 1.0, "a scan"));

  Scene scene = bareScene();
  addWorld(scene, simulation.world());
  const Eigen::Vector4d red(1, 0, 0, 1);
  scene.point_sets.push_back(lidarHits(lidar->latest(), red, 4));
  // Above the middle of the room, looking down on the inner faces of the walls, where the beams end.
  scene.camera = Camera::perspective({0, 0, 6}, {0, 0, 0}, Eigen::Vector3d::UnitY(), 70 * M_PI / 180);
  const Image image = OffscreenRenderer().render(scene, kWidth, kHeight);

  // The mast at the origin sweeps -90 to 90 degrees 0.5 m up, at most 2.5 m: it reaches the side walls at
  // y = +-2 beyond 53 degrees either side, and not the east wall 3 m ahead.
  const std::vector<Eigen::Vector3d>& hits = scene.point_sets[0].points;
  EXPECT_GT(hits.size(), 60u);
  for (const Eigen::Vector3d& hit : hits) {
    EXPECT_NEAR(std::abs(hit.y()), 2, 1e-3);
    EXPECT_NEAR(hit.z(), 0.5, 1e-3);
    const Eigen::Vector2i pixel = pixelOf(scene.camera, hit, kWidth, kHeight);
    EXPECT_EQ(rgbAt(image, pixel.x(), pixel.y()), Eigen::Vector3i(255, 0, 0))
        << "hit " << hit.transpose() << " at pixel " << pixel.transpose();
  }
  const Eigen::Vector2i east_wall = pixelOf(scene.camera, {3, 0, 0.5}, kWidth, kHeight);
  EXPECT_NE(rgbAt(image, east_wall.x(), east_wall.y()), Eigen::Vector3i(255, 0, 0)) << "no hit beyond 2.5 m";
}

TEST(Render, PointsBehindAMeshAreHiddenUnlessTheyAreAnOverlay) {
  Scene scene = bareScene();
  scene.meshes.push_back(box({2, 2, 1}, {0, 0, 0.5}, {0.2, 0.6, 0.2, 1}));  // top face at z = 1
  PointSet hidden, overlay;
  hidden.points = {{-0.5, 0, 0.5}};
  overlay.points = {{0.5, 0, 0.5}};
  overlay.overlay = true;
  scene.point_sets = {hidden, overlay};
  scene.camera = Camera::topDown(Eigen::Vector2d::Zero(), Eigen::Vector2d(2, 2));
  const Image image = OffscreenRenderer().render(scene, kWidth, kHeight);
  const auto colour_at = [&](const Eigen::Vector3d& point) {
    const Eigen::Vector2i pixel = pixelOf(scene.camera, point, kWidth, kHeight);
    return rgbAt(image, pixel.x(), pixel.y());
  };
  EXPECT_EQ(colour_at(overlay.points[0]), Eigen::Vector3i(255, 0, 0));
  EXPECT_TRUE(sameColour(colour_at(hidden.points[0]),
                         bytes(scene.lighting.shade({0.2, 0.6, 0.2, 1}, Eigen::Vector3d::UnitZ()))));
}

TEST(Render, SeeThroughMeshesBlendOverWhatIsBehindThem) {
  Scene scene = bareScene();
  scene.meshes.push_back(box({2, 2, 1}, {0, 0, -0.5}, {1, 0, 0, 1}));    // opaque red, top at z = 0
  scene.meshes.push_back(box({1, 1, 1}, {0, 0, 0.5}, {0, 0, 1, 0.25}));  // a quarter-opaque blue cube on it
  scene.lighting = {-Eigen::Vector3d::UnitZ(), /*ambient=*/0, /*diffuse=*/1};  // tops in their full colour
  scene.camera = Camera::topDown(Eigen::Vector2d::Zero(), Eigen::Vector2d(2, 2));
  const Image image = OffscreenRenderer().render(scene, kWidth, kHeight);
  const auto pixel = image.at(kWidth / 2, kHeight / 2);
  EXPECT_TRUE(sameColour(Eigen::Vector3i(pixel[0], pixel[1], pixel[2]), bytes({0.75, 0, 0.25})));
  EXPECT_EQ(pixel[3], 255) << "the picture stays opaque";
  const Eigen::Vector2i red_only = pixelOf(scene.camera, {0.8, 0, 0}, kWidth, kHeight);
  EXPECT_EQ(rgbAt(image, red_only.x(), red_only.y()), Eigen::Vector3i(255, 0, 0));
}

TEST(Render, PolylineIsDrawnAlongItsPoints) {
  Scene scene = bareScene();
  Polyline trail;
  trail.points = {{-2, -1, 0}, {0, -1, 0}, {1, 1, 0}};
  trail.rgba = {0, 0.6, 0, 1};
  trail.width = 3;
  scene.polylines.push_back(trail);
  scene.camera = Camera::topDown(Eigen::Vector2d::Zero(), Eigen::Vector2d(3, 3));
  const Image image = OffscreenRenderer().render(scene, kWidth, kHeight);
  const Eigen::Vector3i green = bytes({0, 0.6, 0});
  for (const Eigen::Vector3d& on_line : {Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(0.5, 0, 0)}) {
    const Eigen::Vector2i pixel = pixelOf(scene.camera, on_line, kWidth, kHeight);
    EXPECT_TRUE(sameColour(rgbAt(image, pixel.x(), pixel.y()), green)) << on_line.transpose();
  }
  const Eigen::Vector2i off_line = pixelOf(scene.camera, {-1, 0, 0}, kWidth, kHeight);
  EXPECT_TRUE(isBackground(image, off_line.x(), off_line.y()));
}

/// The mean pixel of the pixels in `rgb`'s colour; nullopt when there is none.
std::optional<Eigen::Vector2d> centroidOf(const Image& image, const Eigen::Vector3i& rgb) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int count = 0;
  for (int row = 0; row < image.height; ++row) {
    for (int column = 0; column < image.width; ++column) {
      if (!sameColour(rgbAt(image, column, row), rgb)) continue;
      sum += Eigen::Vector2d(column + 0.5, row + 0.5);
      ++count;
    }
  }
  if (count == 0) return std::nullopt;
  return sum / count;
}

TEST(Render, ImagesAreNeitherUpsideDownNorMirrored) {
  Scene scene = bareScene();
  const Eigen::Vector4d red(1, 0, 0, 1), blue(0, 0, 1, 1);
  scene.meshes.push_back(box({1, 1, 1}, {0, 2, 0}, red));   // north
  scene.meshes.push_back(box({1, 1, 1}, {2, 0, 0}, blue));  // east
  // Lit from straight above, the top faces show their full colour.
  scene.lighting.direction = -Eigen::Vector3d::UnitZ();
  scene.lighting.ambient = 0;
  scene.lighting.diffuse = 1;
  OffscreenRenderer renderer;

  // Plan: +x to the right, +y up; each box 1 m = 1 / 8 of the 8 m wide view.
  scene.camera = Camera::topDown(Eigen::Vector2d::Zero(), Eigen::Vector2d(4, 3));
  Image image = renderer.render(scene, kWidth, kHeight);
  const double pixels_per_metre = kWidth / 8.0;
  auto north = centroidOf(image, Eigen::Vector3i(255, 0, 0));
  auto east = centroidOf(image, Eigen::Vector3i(0, 0, 255));
  ASSERT_TRUE(north && east);
  EXPECT_NEAR(north->x(), kWidth / 2.0, 1);
  EXPECT_NEAR(north->y(), kHeight / 2.0 - 2 * pixels_per_metre, 1) << "+y is up";
  EXPECT_NEAR(east->x(), kWidth / 2.0 + 2 * pixels_per_metre, 1) << "+x is right";
  EXPECT_NEAR(east->y(), kHeight / 2.0, 1);

  // Perspective from the south, looking north with z up: the east box is on the right, the north box ahead.
  // The camera's pose as a ROS body frame: yawed to +y, pitched down to the origin.
  Eigen::Isometry3d camera_pose(Eigen::Translation3d(0, -6, 4));
  camera_pose.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(std::atan2(4, 6), Eigen::Vector3d::UnitY()));
  scene.camera = cameraAt(camera_pose);
  EXPECT_TRUE(
      scene.camera.viewMatrix().isApprox(Camera::perspective({0, -6, 4}, {0, 0, 0}).viewMatrix(), 1e-12));
  scene.lighting.direction = Eigen::Vector3d(0, 1, 0);
  image = renderer.render(scene, kWidth, kHeight);
  north = centroidOf(image, Eigen::Vector3i(255, 0, 0));
  east = centroidOf(image, Eigen::Vector3i(0, 0, 255));
  ASSERT_TRUE(north && east);
  EXPECT_GT(east->x(), kWidth / 2.0 + 20) << "+x is right when looking along +y";
  EXPECT_NEAR(north->x(), kWidth / 2.0, 2);
  EXPECT_LT(north->y(), east->y()) << "the farther box is higher in the picture, looking down";
}

TEST(Camera, ChaseAndFrontViewsFrameTheRobotFromBehindAndFromAhead) {
  // A robot 1 m x 0.6 m x 0.8 m at (1, 2), heading +y.
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(0.7, 1.5, 0), Eigen::Vector3d(1.3, 2.5, 0.8));
  Eigen::Isometry3d pose(Eigen::Translation3d(1, 2, 0));
  pose.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const Camera chase = chaseCamera(pose, bounds), front = frontCamera(pose, bounds);
  for (const Camera& camera : {chase, front}) {
    EXPECT_TRUE(camera.target.isApprox(bounds.center()));
    EXPECT_NEAR(camera.eye.x(), 1, 1e-9) << "in line with the heading";
    EXPECT_GT(camera.eye.z(), bounds.max().z()) << "above the robot";
    for (int corner = 0; corner < 8; ++corner) {
      const auto pixel = camera.project(bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)),
                                        kWidth, kHeight);
      ASSERT_TRUE(pixel);
      EXPECT_TRUE(pixel->x() > 0 && pixel->x() < kWidth && pixel->y() > 0 && pixel->y() < kHeight)
          << "the whole robot is in the picture";
    }
  }
  EXPECT_LT(chase.eye.y(), 1.5) << "behind";
  EXPECT_GT(front.eye.y(), 2.5) << "ahead";
  // Both keep the whole robot in front of the near clip plane, which cuts away walls between camera and
  // robot.
  for (const Camera& camera : {chase, front}) {
    const Eigen::Vector3d forward = (camera.target - camera.eye).normalized();
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d point = bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
      EXPECT_GT((point - camera.eye).dot(forward), camera.near_clip);
    }
  }
}

TEST(Render, ReusesTheRendererAcrossSizesAndMoves) {
  Scene scene = bareScene();
  scene.meshes.push_back(box({1, 1, 1}, Eigen::Vector3d::Zero(), {0, 0, 1, 1}));
  scene.camera = Camera::topDown(Eigen::Vector2d::Zero(), Eigen::Vector2d(1, 1));
  OffscreenRenderer first;
  const Image big = first.render(scene, 200, 100);
  const Image small = first.render(scene, 50, 40);
  OffscreenRenderer moved = std::move(first);
  const Image again = moved.render(scene, 200, 100);
  EXPECT_EQ(small.width, 50);
  EXPECT_EQ(small.rgba.size(), 50u * 40 * 4);
  EXPECT_EQ(again.rgba, big.rgba);
  EXPECT_FALSE(isBackground(small, 25, 20)) << "the box is in the middle";
  EXPECT_THROW(moved.render(scene, 0, 10), std::invalid_argument);
}

TEST(Png, WritesWhatItReadsBack) {
  Image image{37, 23, {}};  // odd sizes: no row padding can hide
  for (int row = 0; row < image.height; ++row) {
    for (int column = 0; column < image.width; ++column) {
      image.rgba.insert(image.rgba.end(),
                        {static_cast<uint8_t>(7 * column), static_cast<uint8_t>(11 * row),
                         static_cast<uint8_t>(column ^ row), static_cast<uint8_t>(255 - row)});
    }
  }
  const std::string path = temporaryPath(".png");
  std::string error;
  ASSERT_TRUE(writePng(path, image, &error)) << error;
  const Image read = readPng(path);
  std::remove(path.c_str());
  EXPECT_EQ(read.width, image.width);
  EXPECT_EQ(read.height, image.height);
  EXPECT_EQ(read.rgba, image.rgba);
}

TEST(Png, AnUnwritablePathGivesFalseAndSaysWhy) {
  const Image image{2, 2, std::vector<uint8_t>(16, 128)};
  std::string error;
  EXPECT_FALSE(writePng("/nonexistent_directory/robot.png", image, &error));
  EXPECT_THAT(error, HasSubstr("[/nonexistent_directory/robot.png]"));
  EXPECT_THAT(error, HasSubstr("No such file or directory"));
}

/// Expands, loads and snapshots a robot in empty.world as render_model does, collecting every load message.
/// `world_meshes`: how many of the scene's meshes, the first ones, are the world's.
RobotSnapshot snapshotShippedRobot(const std::string& package, const std::string& xacro,
                                   std::vector<std::string>& warnings, size_t* world_meshes) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  ModelSpec model = parseModel(test::expandXacro(package, xacro), package, resolver, &warnings);
  WorldSpec world = loadWorld(test::packageFile("bullet_sim", "worlds/empty.world"), resolver, &warnings);
  *world_meshes = 0;
  for (const WorldModelSpec& world_model : world.models) *world_meshes += world_model.visuals.size();
  RobotSnapshot snapshot = snapshotRobot(std::move(world), std::move(model), {}, View::kChase);
  warnings.insert(warnings.end(), snapshot.warnings.begin(), snapshot.warnings.end());
  return snapshot;
}

TEST(RenderModel, EveryShippedRobotRendersWithoutWarnings) {
  const std::pair<std::string, std::string> robots[] = {
      {"smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro"},
      {"smartcar_description", "urdf/smartcar.urdf.xacro"},
      {"yahboomcar_description", "urdf/yahboomcar.urdf.xacro"}};
  OffscreenRenderer renderer;
  for (const auto& [package, xacro] : robots) {
    SCOPED_TRACE(package);
    std::vector<std::string> warnings;
    size_t world_meshes = 0;
    RobotSnapshot snapshot = snapshotShippedRobot(package, xacro, warnings, &world_meshes);
    std::string said;
    for (const auto& warning : warnings) said += warning + "\n";
    EXPECT_TRUE(warnings.empty()) << said;
    EXPECT_EQ(snapshot.scene.point_sets.size(), 1u) << "its lidar scanned";

    // The robot is what changes when its meshes are left out.
    const Image with_robot = renderer.render(snapshot.scene, kWidth, kHeight);
    ASSERT_GT(snapshot.scene.meshes.size(), world_meshes);
    snapshot.scene.meshes.resize(world_meshes);
    const Image without = renderer.render(snapshot.scene, kWidth, kHeight);
    const int robot_pixels = countPixels(
        with_robot, [&](int c, int r) { return rgbAt(with_robot, c, r) != rgbAt(without, c, r); });
    EXPECT_GT(robot_pixels, 0.02 * kWidth * kHeight);
    EXPECT_LT(robot_pixels, 0.4 * kWidth * kHeight);
  }
}

TEST(RenderModel, WritesAPngOfTheRequestedSize) {
  const std::string out = temporaryPath(".png");
  const test::CommandResult result =
      test::run(std::string(RENDER_MODEL) + " --xacro '" +
                test::packageFile("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro") +
                "' --world home.world --view top --size 320x200 --out " + out);
  EXPECT_EQ(result.status, 0) << result.errors;
  EXPECT_EQ(result.errors, "") << "nothing alarming";
  const Image image = readPng(out);
  std::remove(out.c_str());
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 200);
}

TEST(RenderModel, CameraViewsAreTheCamerasOwnImageAtItsSize) {
  const std::string out = temporaryPath(".png");
  const std::string robot =
      "--urdf '" + test::fixture("robots/depth_camera_box.urdf") + "' --world home.world";
  test::CommandResult result = test::run(std::string(RENDER_MODEL) + " " + robot +
                                         " --pose -2,0,0 --view depth:depth_camera --out " + out);
  ASSERT_EQ(result.status, 0) << result.errors;
  const Image depth = readPng(out);
  std::remove(out.c_str());
  EXPECT_EQ(depth.width, 640);
  EXPECT_EQ(depth.height, 480);
  // The floor just below the view centre is nearer than the far wall above it: brighter in a depth picture.
  EXPECT_GT(rgbAt(depth, 320, 470)[0], rgbAt(depth, 320, 100)[0]);

  result = test::run(std::string(RENDER_MODEL) + " " + robot + " --view camera:nope --out " + out);
  EXPECT_EQ(result.status, 1);
  EXPECT_THAT(result.errors, HasSubstr("no robot has a camera [nope]; the cameras are: [depth_camera]"));
}

TEST(RenderModel, BadArgumentsPrintTheUsageAndExitWith2) {
  for (const std::string args :
       {"", "--urdf x.urdf", "--urdf x.urdf --out y.png --view side", "--urdf x.urdf --out y.png --size 640",
        "--urdf x.urdf --xacro y --out z.png"}) {
    SCOPED_TRACE(args);
    const test::CommandResult result = test::run(std::string(RENDER_MODEL) + " " + args);
    EXPECT_EQ(result.status, 2);
    EXPECT_THAT(result.errors, HasSubstr("usage: render_model"));
  }
}

TEST(RenderModel, AnUnwritableOutputSaysSoAndExitsWith1) {
  const test::CommandResult result =
      test::run(std::string(RENDER_MODEL) + " --urdf '" + test::fixture("robots/lidar_mast.urdf") +
                "' --out /nonexistent_directory/robot.png");
  EXPECT_EQ(result.status, 1);
  EXPECT_THAT(result.errors,
              HasSubstr("cannot write PNG [/nonexistent_directory/robot.png]: No such file or directory"));
}
}  // namespace
}  // namespace bullet_sim

namespace bullet_sim {
namespace {

TEST(Recording, TrailsGrowEveryTenthOfASecondAndFramesComeAtTheirPeriod) {
  Simulation simulation(test::shippedWorld("empty.world"));
  simulation.spawn("chair", test::wheelchair(), {});
  Recording recording(/*frame_period=*/0.25);
  std::vector<std::string> frames;
  for (int i = 0; i < 1000; ++i) {  // 1 s at 1 ms
    simulation.step();
    if (const auto frame = recording.afterStep(simulation)) frames.push_back(*frame);
  }
  EXPECT_EQ(frames, (std::vector<std::string>{"frame_000001.png", "frame_000002.png", "frame_000003.png",
                                              "frame_000004.png"}));
  ASSERT_EQ(recording.trails().size(), 1u);
  EXPECT_EQ(recording.trails().front().points.size(), 10u);  // at 0.001 s, then every 0.1 s

  recording.restart();
  simulation.resetSimulation();
  EXPECT_TRUE(recording.trails().empty());
  for (int i = 0; i < 250; ++i) simulation.step();
  EXPECT_EQ(recording.afterStep(simulation), std::optional<std::string>("frame_000005.png"));
  recording.forget("chair");
  EXPECT_TRUE(recording.trails().empty());
}

}  // namespace
}  // namespace bullet_sim
