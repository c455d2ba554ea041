// Checks the ray caster against analytic distances: boxes exactly, spheres, cylinders and planes to 1 mm,
// with no grazing false hits, and its max range, ignored body, moving bodies and determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "bullet_sim/sensing/ray_caster.h"

namespace bullet_sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kBoxTolerance = 1e-4;     // [m] boxes are triangulated exactly
constexpr double kCurvedTolerance = 1e-3;  // [m] spheres, cylinders, planes
constexpr double kMaxRange = 100;          // [m]

Eigen::Isometry3d translation(double x, double y, double z) {
  return Eigen::Isometry3d(Eigen::Translation3d(x, y, z));
}

Collision box(const Eigen::Vector3d& size, const Eigen::Isometry3d& origin) {
  Collision collision;
  collision.origin = origin;
  collision.shape.type = Shape::Type::kBox;
  collision.shape.box_size = size;
  return collision;
}

Collision sphere(double radius, const Eigen::Isometry3d& origin) {
  Collision collision;
  collision.origin = origin;
  collision.shape.type = Shape::Type::kSphere;
  collision.shape.radius = radius;
  return collision;
}

Collision cylinder(double radius, double length, const Eigen::Isometry3d& origin) {
  Collision collision;
  collision.origin = origin;
  collision.shape.type = Shape::Type::kCylinder;
  collision.shape.radius = radius;
  collision.shape.length = length;
  return collision;
}

Collision groundPlane() {
  Collision collision;
  collision.shape.type = Shape::Type::kPlane;
  collision.shape.plane_normal = Eigen::Vector3d::UnitZ();
  return collision;
}

/// Walls 1 m high and 0.1 m thick whose inner faces are at x = +-3 and y = +-2.
std::vector<Collision> room() {
  return {box({0.1, 4.2, 1}, translation(3.05, 0, 0.5)), box({0.1, 4.2, 1}, translation(-3.05, 0, 0.5)),
          box({6.2, 0.1, 1}, translation(0, 2.05, 0.5)), box({6.2, 0.1, 1}, translation(0, -2.05, 0.5))};
}

std::vector<Eigen::Vector3f> horizontalDirections(int count) {
  std::vector<Eigen::Vector3f> directions;
  for (int i = 0; i < count; ++i) {
    const double angle = 2 * M_PI * i / count;
    directions.emplace_back(std::cos(angle), std::sin(angle), 0);
  }
  return directions;
}

/// A 3D lidar's rays: `columns` azimuths times `rows` elevations in [-15, 15] degrees.
std::vector<Eigen::Vector3f> lidarDirections(int columns, int rows) {
  std::vector<Eigen::Vector3f> directions;
  for (int row = 0; row < rows; ++row) {
    const double elevation = (-15 + 30.0 * row / (rows - 1)) * M_PI / 180;
    for (int column = 0; column < columns; ++column) {
      const double azimuth = 2 * M_PI * column / columns;
      directions.emplace_back(std::cos(elevation) * std::cos(azimuth),
                              std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    }
  }
  return directions;
}

double castOne(const RayCaster& caster, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
               double max_range = kMaxRange, BodyId ignore = kNoBody) {
  std::vector<double> ranges;
  caster.cast(origin, {direction.normalized().cast<float>()}, max_range, ignore, ranges);
  return ranges.at(0);
}

/// Distance along the unit `direction` from `origin` to a sphere or, with z ignored, to an infinite
/// z-cylinder; nullopt-like -1 when the line misses. `tangency` receives how far the line passes from
/// tangency [m].
double distanceToRound(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                       const Eigen::Vector3d& center, double radius, double* tangency) {
  const Eigen::Vector3d to_center = center - origin;
  const double along = to_center.dot(direction);
  const double miss_distance = (to_center - along * direction).norm();
  *tangency = std::abs(miss_distance - radius);
  if (miss_distance > radius || along < 0) return -1;
  return along - std::sqrt(radius * radius - miss_distance * miss_distance);
}

TEST(RayCasterTest, BoxRoomRangesAreExact) {
  RayCaster caster;
  caster.addBody(room(), Eigen::Isometry3d::Identity(), true);
  caster.addBody({groundPlane()}, Eigen::Isometry3d::Identity(), true);
  caster.commit();

  const Eigen::Vector3d origin(0.5, -0.3, 0.4);
  const std::vector<Eigen::Vector3f> directions = horizontalDirections(360);
  std::vector<double> ranges;
  caster.cast(origin, directions, kMaxRange, kNoBody, ranges);
  ASSERT_EQ(ranges.size(), directions.size());
  for (size_t i = 0; i < directions.size(); ++i) {
    const Eigen::Vector3d direction = directions[i].cast<double>();
    double expected = kInf;
    for (int axis = 0; axis < 2; ++axis) {
      const double wall = axis == 0 ? 3 : 2;
      if (direction[axis] != 0)
        expected =
            std::min(expected, (std::copysign(wall, direction[axis]) - origin[axis]) / direction[axis]);
    }
    EXPECT_NEAR(ranges[i], expected, kBoxTolerance) << "ray " << i;
  }
}

TEST(RayCasterTest, SphereMatchesAnalyticIncludingGrazingRays) {
  const Eigen::Vector3d center(3, 0.2, 0.5);
  const double radius = 0.5;
  RayCaster caster;
  caster.addBody({sphere(radius, translation(center.x(), center.y(), center.z()))},
                 Eigen::Isometry3d::Identity(), true);
  caster.commit();

  // A cone of rays around the sphere, densest near its silhouette.
  const Eigen::Vector3d origin(0, 0, 0.3);
  int hits = 0;
  int checked = 0;
  for (int a = -60; a <= 60; ++a) {
    for (int e = -60; e <= 60; e += 3) {
      const Eigen::Vector3d direction =
          (center - origin + Eigen::Vector3d(0, 0.012 * a, 0.012 * e)).normalized();
      double tangency;
      const double expected = distanceToRound(origin, direction, center, radius, &tangency);
      if (tangency < kCurvedTolerance) continue;
      ++checked;
      const double range = castOne(caster, origin, direction);
      if (expected < 0) {
        EXPECT_EQ(range, kInf) << "a " << a << " e " << e;
      } else {
        ++hits;
        EXPECT_NEAR(range, expected, kCurvedTolerance) << "a " << a << " e " << e;
      }
    }
  }
  EXPECT_GT(hits, checked / 4);
  EXPECT_LT(hits, checked);
}

TEST(RayCasterTest, CylinderMatchesAnalyticOnSideAndCap) {
  // Axis along z at (0, 2.5), from z = 0 to 0.8.
  const Eigen::Vector3d center(0, 2.5, 0.4);
  const double radius = 0.3;
  RayCaster caster;
  caster.addBody({cylinder(radius, 0.8, translation(center.x(), center.y(), center.z()))},
                 Eigen::Isometry3d::Identity(), true);
  caster.commit();

  // Horizontal rays sweeping across the side, through both tangents.
  const Eigen::Vector3d origin(0, 0, 0.4);
  int hits = 0;
  for (int i = -400; i <= 400; ++i) {
    const double angle = M_PI / 2 + 0.0005 * i;
    const Eigen::Vector3d direction(std::cos(angle), std::sin(angle), 0);
    double tangency;
    const double expected = distanceToRound(origin, direction, center, radius, &tangency);
    if (tangency < kCurvedTolerance) continue;
    const double range = castOne(caster, origin, direction);
    if (expected < 0) {
      EXPECT_EQ(range, kInf) << "ray " << i;
    } else {
      ++hits;
      EXPECT_NEAR(range, expected, kCurvedTolerance) << "ray " << i;
    }
  }
  EXPECT_GT(hits, 100);

  // Vertical rays down onto the top cap and past its rim.
  for (int i = -50; i <= 50; ++i) {
    const double offset = 0.01 * i;
    if (std::abs(std::abs(offset) - radius) < kCurvedTolerance) continue;
    const double range = castOne(caster, {offset, 2.5, 2}, -Eigen::Vector3d::UnitZ());
    if (std::abs(offset) < radius)
      EXPECT_NEAR(range, 1.2, kCurvedTolerance) << "offset " << offset;
    else
      EXPECT_EQ(range, kInf) << "offset " << offset;
  }

  // Oblique rays from above that reach the cap before the side.
  const Eigen::Vector3d high_origin(0, 0, 1.5);
  for (int i = -25; i <= 25; ++i) {
    const Eigen::Vector3d target(0.005 * i, 2.5 + 0.01 * i, 0.8);
    EXPECT_NEAR(castOne(caster, high_origin, target - high_origin), (target - high_origin).norm(),
                kCurvedTolerance)
        << "target " << target.transpose();
  }
}

TEST(RayCasterTest, GroundPlaneHitsAtAnalyticDistanceAndNeverGrazing) {
  RayCaster caster;
  caster.addBody({groundPlane()}, Eigen::Isometry3d::Identity(), true);
  caster.commit();

  EXPECT_NEAR(castOne(caster, {1, 1, 0.7}, -Eigen::Vector3d::UnitZ()), 0.7, kCurvedTolerance);
  EXPECT_NEAR(castOne(caster, {-4, 2, 0.7}, {1, 0, -1}), 0.7 * std::sqrt(2), kCurvedTolerance);
  EXPECT_NEAR(castOne(caster, {0, 0, 0.2}, {1, 0, -0.01}), 0.2 * std::sqrt(1 + 1e4), kCurvedTolerance);
  // Horizontal rays just above the plane, and one just rising, never touch it.
  for (const Eigen::Vector3f& direction : horizontalDirections(36))
    EXPECT_EQ(castOne(caster, {0.3, -0.2, 0.001}, direction.cast<double>()), kInf) << direction.transpose();
  EXPECT_EQ(castOne(caster, {0, 0, 0.001}, {1, 0, 1e-6}), kInf);
  // From below, the plane is hit too.
  EXPECT_NEAR(castOne(caster, {0, 0, -0.5}, Eigen::Vector3d::UnitZ()), 0.5, kCurvedTolerance);
}

// A plane off its body's origin and tilted in it, on a body that is raised: met where the plane is, with its
// normal, whether the body is static or moves.
TEST(RayCasterTest, ARaisedTiltedPlaneIsHitWhereItIs) {
  Collision plane = groundPlane();
  plane.origin = translation(0.5, 0, 1);
  plane.origin.rotate(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitY()));
  const Eigen::Isometry3d pose = translation(0, 0, 0.5);
  const Eigen::Vector3d normal(0.5, 0, std::sqrt(3) / 2), on_plane(0.5, 0, 1.5);  // in the world
  const Eigen::Vector3d origin(0, 0.3, 0), up = Eigen::Vector3d::UnitZ();
  const double expected = normal.dot(on_plane - origin) / normal.dot(up);
  for (const bool is_static : {true, false}) {
    SCOPED_TRACE(is_static);
    RayCaster caster;
    caster.addBody({plane}, pose, is_static);
    caster.commit();
    EXPECT_NEAR(castOne(caster, origin, up), expected, kCurvedTolerance);
    if (!is_static) continue;
    std::vector<double> ranges;
    std::vector<Eigen::Vector3d> normals;
    caster.castStatic({origin}, {up}, kMaxRange, ranges, &normals);
    EXPECT_NEAR(ranges.at(0), expected, kCurvedTolerance);
    EXPECT_TRUE(normals.at(0).isApprox(-normal, 1e-6)) << normals.at(0).transpose();  // facing the ray
  }
}

// castStatic meets a world of planes alone in double precision, and the same planes among other static shapes
// through Embree, in float: the nearest surface either way, its normal facing the ray.
TEST(RayCasterTest, CastStaticMeetsPlanesAloneInDoublePrecision) {
  Collision ceiling = groundPlane();
  ceiling.origin = translation(0, 0, 2.5);
  const Eigen::Vector3d origin(0.1, 0.2, 0.3), up = Eigen::Vector3d::UnitZ();
  const std::vector<Eigen::Vector3d> origins(3, origin), directions{-up, up, Eigen::Vector3d::UnitX()};
  RayCaster caster;
  caster.addBody({groundPlane(), ceiling}, Eigen::Isometry3d::Identity(), true);
  caster.commit();
  std::vector<double> ranges;
  std::vector<Eigen::Vector3d> normals;
  caster.castStatic(origins, directions, kMaxRange, ranges, &normals);
  EXPECT_DOUBLE_EQ(ranges.at(0), 0.3);  // a float ray is 1e-8 off
  EXPECT_DOUBLE_EQ(ranges.at(1), 2.2);
  EXPECT_EQ(ranges.at(2), kInf);
  EXPECT_EQ(normals.at(0), up);
  EXPECT_EQ(normals.at(1), -up);
  // A box beside them: Embree meets all three, the planes as before.
  caster.addBody({box({0.2, 0.2, 0.2}, translation(1.1, 0.2, 0.3))}, Eigen::Isometry3d::Identity(), true);
  caster.commit();
  caster.castStatic(origins, directions, kMaxRange, ranges, &normals);
  EXPECT_NEAR(ranges.at(0), 0.3, kCurvedTolerance);
  EXPECT_NE(ranges.at(0), 0.3);
  EXPECT_NEAR(ranges.at(1), 2.2, kCurvedTolerance);
  EXPECT_NEAR(ranges.at(2), 0.9, kBoxTolerance);
  EXPECT_TRUE(normals.at(1).isApprox(-up, 1e-6)) << normals.at(1).transpose();
}

// castStatic tells the mu of each static collision it hits (a raycast wheel grips by the lesser of its own
// and the ground's), among planes alone and through Embree: analytic shapes, and each shape of a body's
// triangles.
TEST(RayCasterTest, CastStaticTellsTheFrictionOfWhatEachRayHits) {
  Collision floor = groundPlane(), ceiling = groundPlane();
  floor.mu = 0.3;
  ceiling.origin = translation(0, 0, 2.5);
  ceiling.mu = 0.6;
  const Eigen::Vector3d origin(0.1, 0.2, 0.3), up = Eigen::Vector3d::UnitZ();
  const std::vector<Eigen::Vector3d> origins(4, origin),
      directions{-up, up, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  RayCaster caster;
  caster.addBody({floor, ceiling}, Eigen::Isometry3d::Identity(), true);
  caster.commit();
  std::vector<double> ranges, frictions;
  caster.castStatic(origins, directions, kMaxRange, ranges, nullptr, &frictions);
  EXPECT_EQ(frictions.at(0), 0.3);
  EXPECT_EQ(frictions.at(1), 0.6);
  Collision ahead = box({0.2, 0.2, 0.2}, translation(1.1, 0.2, 0.3));
  Collision aside = box({0.2, 0.2, 0.2}, translation(0.1, 1.2, 0.3));
  ahead.mu = 0.2;
  aside.mu = 0.9;
  caster.addBody({ahead, aside}, Eigen::Isometry3d::Identity(), true);
  caster.commit();
  caster.castStatic(origins, directions, kMaxRange, ranges, nullptr, &frictions);
  EXPECT_NEAR(ranges.at(3), 0.9, kBoxTolerance);
  EXPECT_EQ(frictions, (std::vector<double>{0.3, 0.6, 0.2, 0.9}));
}

TEST(RayCasterTest, MeshTrianglesAreExact) {
  auto square = std::make_shared<TriangleMesh>();  // 1 m square in the mesh's y-z plane
  square->vertices = {{0, -0.5, -0.5}, {0, 0.5, -0.5}, {0, 0.5, 0.5}, {0, -0.5, 0.5}};
  square->triangles = {{0, 1, 2}, {0, 2, 3}};
  Collision mesh;
  mesh.origin = translation(1.5, 0, 0);
  mesh.shape.type = Shape::Type::kMesh;
  mesh.shape.mesh = square;
  RayCaster caster;
  caster.addBody({mesh}, translation(0, 0, 1), false);
  caster.commit();

  EXPECT_NEAR(castOne(caster, {0, 0, 1}, Eigen::Vector3d::UnitX()), 1.5, kBoxTolerance);
  EXPECT_NEAR(castOne(caster, {0, 0, 1}, {1.5, 0.3, -0.2}), Eigen::Vector3d(1.5, 0.3, -0.2).norm(),
              kBoxTolerance);
  EXPECT_EQ(castOne(caster, {0, 0, 1}, {1.5, 0.6, 0}), kInf);
}

size_t threadsOfThisProcess() {
  return static_cast<size_t>(std::distance(std::filesystem::directory_iterator("/proc/self/task"),
                                           std::filesystem::directory_iterator()));
}

// Scenes are built on the calling thread: Embree's TBB workers, woken by each step's rebuild of the top tree,
// would spin on a core the simulation's pool and the node's other processes want.
TEST(RayCasterTest, BuildsItsScenesOnTheCallingThreadAlone) {
  const size_t before = threadsOfThisProcess();
  auto grid = std::make_shared<TriangleMesh>();  // 20,000 triangles: large enough for a parallel build
  constexpr int kCells = 100;
  for (int i = 0; i <= kCells; ++i) {
    for (int j = 0; j <= kCells; ++j) grid->vertices.push_back({0.01 * i, 0.01 * j, 0});
  }
  for (int i = 0; i < kCells; ++i) {
    for (int j = 0; j < kCells; ++j) {
      const int corner = i * (kCells + 1) + j;
      grid->triangles.push_back({corner, corner + 1, corner + kCells + 2});
      grid->triangles.push_back({corner, corner + kCells + 2, corner + kCells + 1});
    }
  }
  Collision floor;
  floor.shape.type = Shape::Type::kMesh;
  floor.shape.mesh = grid;
  RayCaster caster;
  caster.addBody({floor}, Eigen::Isometry3d::Identity(), true);
  const BodyId moving =
      caster.addBody({sphere(0.1, Eigen::Isometry3d::Identity())}, translation(0.5, 0.5, 1), false);
  caster.commit();
  for (int step = 0; step < 50; ++step) {
    caster.setPose(moving, translation(0.5, 0.5, 1 + 0.01 * step));
    caster.commit();
    EXPECT_NEAR(castOne(caster, {0.3, 0.3, 0.5}, -Eigen::Vector3d::UnitZ()), 0.5, kBoxTolerance);
  }
  EXPECT_EQ(threadsOfThisProcess(), before);
}

TEST(RayCasterTest, WallBeyondMaxRangeIsNotHit) {
  RayCaster caster;
  caster.addBody({box({0.1, 4, 2}, translation(5.05, 0, 0))}, Eigen::Isometry3d::Identity(), true);
  caster.commit();

  EXPECT_EQ(castOne(caster, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 4.9), kInf);
  EXPECT_NEAR(castOne(caster, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 5.5), 5, kBoxTolerance);
  EXPECT_EQ(castOne(caster, Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitX(), 5.5), kInf);
}

TEST(RayCasterTest, IgnoredBodyEnclosingTheOriginIsSkipped) {
  // The sensor's link: a box inside a sphere, both around the origin; walls at x = 2 and x = -3.
  const std::vector<Collision> link = {box({0.4, 0.4, 0.4}, Eigen::Isometry3d::Identity()),
                                       sphere(0.5, Eigen::Isometry3d::Identity())};
  const std::vector<Collision> walls = {box({0.1, 4, 2}, translation(2.05, 0, 0)),
                                        box({0.1, 4, 2}, translation(-3.05, 0, 0))};
  const Eigen::Isometry3d link_pose = translation(0, 0, 0.4);
  const Eigen::Vector3d origin(0, 0, 0.4);
  // Moving bodies ignored by a mask of their own until the 4,495 masks run out, by the filter after that.
  enum class Link { kMoving, kMovingWithoutMask, kStatic };
  for (const Link kind : {Link::kMoving, Link::kMovingWithoutMask, Link::kStatic}) {
    SCOPED_TRACE(static_cast<int>(kind));
    RayCaster caster;
    const BodyId walls_id = caster.addBody(walls, Eigen::Isometry3d::Identity(), true);
    if (kind == Link::kMovingWithoutMask) {
      for (int i = 0; i < 4495; ++i) caster.addBody(link, translation(10, 10 + i, 0), false);
    }
    const BodyId link_id = caster.addBody(link, link_pose, kind == Link::kStatic);
    caster.commit();

    EXPECT_NEAR(castOne(caster, origin, Eigen::Vector3d::UnitX()), 0.2, kBoxTolerance);
    EXPECT_NEAR(castOne(caster, origin, Eigen::Vector3d::UnitZ()), 0.2, kBoxTolerance);
    EXPECT_NEAR(castOne(caster, origin, Eigen::Vector3d::UnitX(), kMaxRange, walls_id), 0.2, kBoxTolerance);
    EXPECT_NEAR(castOne(caster, origin, Eigen::Vector3d::UnitX(), kMaxRange, link_id), 2, kBoxTolerance);
    EXPECT_NEAR(castOne(caster, origin, -Eigen::Vector3d::UnitX(), kMaxRange, link_id), 3, kBoxTolerance);
    EXPECT_EQ(castOne(caster, origin, Eigen::Vector3d::UnitZ(), kMaxRange, link_id), kInf);
  }
}

TEST(RayCasterTest, IgnoringOneMovingBodyHidesNoOther) {
  // Forty plates 0.1 m thick across the x axis, 1 m apart, the first at x = 0: masks of three bits each, most
  // sharing two with the next. A ray from inside plate k that ignores it meets the plate beyond it, either
  // way, at 0.95 m.
  const std::vector<Collision> plate = {box({0.1, 1, 1}, Eigen::Isometry3d::Identity())};
  RayCaster caster;
  std::vector<BodyId> plates;
  for (int k = 0; k < 40; ++k) plates.push_back(caster.addBody(plate, translation(k, 0, 0), false));
  caster.commit();
  for (int k = 0; k < 40; ++k) {
    SCOPED_TRACE(k);
    const Eigen::Vector3d inside(k, 0, 0);
    if (k + 1 < 40) {
      EXPECT_NEAR(castOne(caster, inside, Eigen::Vector3d::UnitX(), kMaxRange, plates[k]), 0.95,
                  kBoxTolerance);
    }
    if (k > 0) {
      EXPECT_NEAR(castOne(caster, inside, -Eigen::Vector3d::UnitX(), kMaxRange, plates[k]), 0.95,
                  kBoxTolerance);
    }
  }
  // A body added where a plate was removed (it takes the freed mask) is ignored alone as well.
  caster.removeBody(plates[5]);
  const BodyId replacement = caster.addBody(plate, translation(5, 0, 0), false);
  caster.commit();
  EXPECT_NEAR(castOne(caster, Eigen::Vector3d(5, 0, 0), Eigen::Vector3d::UnitX(), kMaxRange, replacement),
              0.95, kBoxTolerance);
  EXPECT_NEAR(castOne(caster, Eigen::Vector3d(4, 0, 0), Eigen::Vector3d::UnitX(), kMaxRange, plates[4]), 0.95,
              kBoxTolerance);
}

TEST(RayCasterTest, MovedBodyIsHitAtItsNewPoseAfterCommit) {
  // A cylinder lying along the body's x axis, and a box 1 m above it.
  const Eigen::Isometry3d along_x(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  const std::vector<Collision> shapes = {cylinder(0.2, 1, along_x),
                                         box({0.4, 0.4, 0.4}, translation(0, 0, 1))};
  const Eigen::Vector3d origin(0, 0, 0.5);
  Eigen::Isometry3d across = translation(2, 0, 0.5);  // axis along world y: the ray meets the side
  across.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const Eigen::Isometry3d lengthwise = translation(3, 0, 0.5);  // axis along world x: the ray meets the cap

  RayCaster caster;
  const BodyId body = caster.addBody(shapes, across, false);
  caster.commit();
  EXPECT_NEAR(castOne(caster, origin, Eigen::Vector3d::UnitX()), 1.8, kCurvedTolerance);
  EXPECT_NEAR(castOne(caster, {2, 0, 3}, -Eigen::Vector3d::UnitZ()), 1.3, kBoxTolerance);

  caster.setPose(body, lengthwise);
  EXPECT_NEAR(castOne(caster, origin, Eigen::Vector3d::UnitX()), 1.8, kCurvedTolerance) << "before commit";
  caster.commit();
  EXPECT_NEAR(castOne(caster, origin, Eigen::Vector3d::UnitX()), 2.5, kCurvedTolerance);
  EXPECT_NEAR(castOne(caster, {3, 0, 3}, -Eigen::Vector3d::UnitZ()), 1.3, kBoxTolerance);
  EXPECT_EQ(castOne(caster, {2, 0, 3}, -Eigen::Vector3d::UnitZ()), kInf);
}

TEST(RayCasterTest, RemovedBodyIsNotHitAfterCommit) {
  RayCaster caster;
  const BodyId near_wall =
      caster.addBody({box({0.1, 4, 2}, translation(1.05, 0, 0))}, translation(0, 0, 0), true);
  caster.addBody({box({0.1, 4, 2}, translation(4.05, 0, 0))}, Eigen::Isometry3d::Identity(), true);
  const BodyId ball =
      caster.addBody({sphere(0.1, Eigen::Isometry3d::Identity())}, translation(0.5, 0, 0), false);
  caster.commit();
  EXPECT_NEAR(castOne(caster, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()), 0.4, kCurvedTolerance);

  caster.removeBody(ball);
  caster.commit();
  EXPECT_NEAR(castOne(caster, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()), 1, kBoxTolerance);
  caster.removeBody(near_wall);
  caster.commit();
  EXPECT_NEAR(castOne(caster, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()), 4, kBoxTolerance);
}

// A body whose physics diverged (a NaN pose) and a sensor riding on one are not Embree's to see: Embree
// aborts the process on a ray that is not finite. Such a ray meets nothing, and such a body hides nothing,
// until its pose is finite again.
TEST(RayCasterTest, NonFiniteRaysMeetNothingAndANonFiniteBodyHidesNothing) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  RayCaster caster;
  caster.addBody({box({0.1, 4, 2}, translation(3.05, 0, 0)), groundPlane()}, Eigen::Isometry3d::Identity(),
                 true);
  const BodyId ball =
      caster.addBody({sphere(0.1, Eigen::Isometry3d::Identity())}, translation(1, 0, 0), false);
  caster.commit();
  EXPECT_NEAR(castOne(caster, {0, 0, 0.5}, Eigen::Vector3d::UnitX()), 3, kBoxTolerance);

  caster.setPose(ball, translation(kNaN, 0, 0));
  caster.commit();
  EXPECT_NEAR(castOne(caster, {0, 0, 0}, Eigen::Vector3d::UnitX()), 3, kBoxTolerance);
  EXPECT_EQ(castOne(caster, {kNaN, 0, 0.5}, Eigen::Vector3d::UnitX()), kInf);
  std::vector<double> ranges;
  const std::vector<Eigen::Vector3f> one_not_finite = {{std::nanf(""), 0, 0}, Eigen::Vector3f::UnitX()};
  caster.cast({0, 0, 0.5}, one_not_finite, kMaxRange, kNoBody, ranges);
  EXPECT_EQ(ranges.at(0), kInf);
  EXPECT_NEAR(ranges.at(1), 3, kBoxTolerance);
  const std::vector<Eigen::Vector3d> down(2, -Eigen::Vector3d::UnitZ());
  caster.castStatic({{kNaN, 0, 1}, {0, 0, 1}}, down, kMaxRange, ranges);
  EXPECT_EQ(ranges.at(0), kInf);
  EXPECT_NEAR(ranges.at(1), 1, kCurvedTolerance);
  RayCaster ground;  // planes alone: castStatic meets them without Embree
  ground.addBody({groundPlane()}, Eigen::Isometry3d::Identity(), true);
  ground.commit();
  ground.castStatic({{kNaN, 0, 1}, {0, 0, 1}}, down, kMaxRange, ranges);
  EXPECT_EQ(ranges.at(0), kInf);
  EXPECT_NEAR(ranges.at(1), 1, kCurvedTolerance);

  caster.setPose(ball, translation(1, 0, 0));
  caster.commit();
  EXPECT_NEAR(castOne(caster, {0, 0, 0}, Eigen::Vector3d::UnitX()), 0.9, kCurvedTolerance);
}

TEST(RayCasterTest, MisuseThrows) {
  RayCaster caster;
  const BodyId wall = caster.addBody({box({0.1, 4, 2}, translation(1.05, 0, 0))}, translation(0, 0, 0), true);
  std::vector<double> ranges;
  EXPECT_THROW(caster.cast(Eigen::Vector3d::Zero(), horizontalDirections(4), kMaxRange, kNoBody, ranges),
               std::logic_error);
  caster.commit();
  EXPECT_THROW(caster.setPose(wall, translation(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(caster.setPose(wall + 1, translation(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(caster.cast(Eigen::Vector3d::Zero(), horizontalDirections(4), kMaxRange, wall + 1, ranges),
               std::invalid_argument);
  caster.removeBody(wall);
  EXPECT_THROW(caster.removeBody(wall), std::invalid_argument);
}

TEST(RayCasterTest, CastsAreDeterministic) {
  const auto build = [] {
    RayCaster caster;
    caster.addBody(room(), Eigen::Isometry3d::Identity(), true);
    caster.addBody({groundPlane()}, Eigen::Isometry3d::Identity(), true);
    caster.addBody({cylinder(0.2, 0.8, translation(1, 1, 0.4)), sphere(0.3, translation(-1, -1, 0.3))},
                   translation(0.2, 0.1, 0), false);
    caster.commit();
    return caster;
  };
  const RayCaster caster = build();
  const std::vector<Eigen::Vector3f> directions = lidarDirections(1800, 16);
  const Eigen::Vector3d origin(0.1, 0.2, 0.5);
  std::vector<double> first, second, other;
  caster.cast(origin, directions, kMaxRange, kNoBody, first);
  caster.cast(origin, directions, kMaxRange, kNoBody, second);
  build().cast(origin, directions, kMaxRange, kNoBody, other);
  ASSERT_EQ(first.size(), directions.size());
  EXPECT_EQ(first, second);  // inf == inf, and no NaN is produced
  EXPECT_EQ(first, other);
}

}  // namespace
}  // namespace bullet_sim
