#include "bullet_sim/sensing/ray_caster.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

namespace bullet_sim {
namespace {

struct ReleaseDevice {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct ReleaseScene {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
struct ReleaseGeometry {
  void operator()(RTCGeometry geometry) const { rtcReleaseGeometry(geometry); }
};
using DeviceHandle = std::unique_ptr<RTCDeviceTy, ReleaseDevice>;
using SceneHandle = std::unique_ptr<RTCSceneTy, ReleaseScene>;
using GeometryHandle = std::unique_ptr<RTCGeometryTy, ReleaseGeometry>;

/// Planes are discs this large [m]: Embree's trees need bounds, and no sensor reaches this far.
constexpr double kPlaneRadius = 1e6;
/// Rays per rtcIntersect16 packet.
constexpr size_t kPacketSize = 16;
/// The geometry mask of everything without a mask of its own (static bodies, and moving bodies beyond the
/// MaskPool's). Rays always include it.
constexpr unsigned kSharedMask = 1;

/// Gives each moving body a mask of its own: three of the 31 bits besides kSharedMask's. A ray that ignores
/// a body clears that body's three bits, and Embree skips the instances whose mask has no bit left in the
/// ray's. Every body has three bits and no two the same three, so that skips the ignored body alone. 4,495
/// bodies get one.
class MaskPool {
 public:
  /// A mask of its own, or kSharedMask once every one is taken.
  unsigned take() {
    if (!released_.empty()) {
      const unsigned mask = released_.back();
      released_.pop_back();
      return mask;
    }
    if (next_ >= kEnd) return kSharedMask;
    const unsigned mask = next_ << 1;  // above kSharedMask's bit
    // The next larger number with as many bits set (Gosper's hack).
    const unsigned lowest = next_ & -next_;
    const unsigned carried = next_ + lowest;
    next_ = carried | (((next_ ^ carried) >> 2) / lowest);
    return mask;
  }
  void give(unsigned mask) {
    if (mask != kSharedMask) released_.push_back(mask);
  }

 private:
  static constexpr unsigned kEnd = 1u << 31;  ///< the three bits are taken from 31
  unsigned next_ = 0b111;
  std::vector<unsigned> released_;
};

/// A sphere, cylinder or plane, intersected in double precision: a sphere or cylinder in its own frame, a
/// plane in the frame. "The frame" is the body frame for a moving body and the world frame for a static one.
struct AnalyticShape {
  Shape::Type type;
  Eigen::Isometry3d frame_from_shape;
  Eigen::Isometry3d shape_from_frame;
  double radius;           ///< kSphere, kCylinder [m]
  double half_length;      ///< kCylinder, along the shape's z [m]
  Eigen::Vector3d normal;  ///< kPlane, unit, in the frame
  double offset;           ///< kPlane [m]: the plane is normal . x = offset in the frame
  RTCBounds bounds;        ///< in the frame [m]
  double mu;               ///< its collision's friction coefficient
};

struct SurfaceHit {
  double t;                ///< ray parameter [m for unit directions]
  Eigen::Vector3d normal;  ///< in the frame of the ray that hit
};

/// Keeps the smallest ray parameter offered within [t_min, t_max].
class ClosestHit {
 public:
  ClosestHit(double t_min, double t_max) : t_min_(t_min), t_max_(t_max) {}
  void offer(double t, const Eigen::Vector3d& normal) {
    if (t < t_min_ || t > t_max_) return;
    t_max_ = t;
    normal_ = normal;
    found_ = true;
  }
  std::optional<SurfaceHit> hit() const {
    return found_ ? std::optional<SurfaceHit>(SurfaceHit{t_max_, normal_}) : std::nullopt;
  }

 private:
  double t_min_;
  double t_max_;
  Eigen::Vector3d normal_ = Eigen::Vector3d::Zero();
  bool found_ = false;
};

/// Both surfaces a ray crosses count: a ray starting inside a shape hits it on the way out. The ray and the
/// normal are in the shape's frame; a plane is not intersected here.
std::optional<SurfaceHit> intersectInShape(const AnalyticShape& shape, const Eigen::Vector3d& origin,
                                           const Eigen::Vector3d& direction, double t_min, double t_max) {
  ClosestHit closest(t_min, t_max);
  const double r = shape.radius;
  switch (shape.type) {
    case Shape::Type::kSphere: {
      const double a = direction.squaredNorm();
      const double b = origin.dot(direction);
      const double discriminant = b * b - a * (origin.squaredNorm() - r * r);
      if (discriminant < 0) break;
      const double root = std::sqrt(discriminant);
      for (const double t : {(-b - root) / a, (-b + root) / a})
        closest.offer(t, (origin + t * direction) / r);
      break;
    }
    case Shape::Type::kCylinder: {
      const double a = direction.head<2>().squaredNorm();
      if (a > 0) {  // else the ray runs along the axis and can only hit the caps
        const double b = origin.head<2>().dot(direction.head<2>());
        const double discriminant = b * b - a * (origin.head<2>().squaredNorm() - r * r);
        if (discriminant >= 0) {
          const double root = std::sqrt(discriminant);
          for (const double t : {(-b - root) / a, (-b + root) / a}) {
            const Eigen::Vector3d point = origin + t * direction;
            if (std::abs(point.z()) <= shape.half_length)
              closest.offer(t, Eigen::Vector3d(point.x(), point.y(), 0) / r);
          }
        }
      }
      if (direction.z() != 0) {
        for (const double side : {-1.0, 1.0}) {
          const double t = (side * shape.half_length - origin.z()) / direction.z();
          if ((origin + t * direction).head<2>().squaredNorm() <= r * r)
            closest.offer(t, Eigen::Vector3d(0, 0, side));
        }
      }
      break;
    }
    default:
      break;
  }
  return closest.hit();
}

/// The ray parameter at which a ray crosses a plane, in the plane's frame. A ray parallel to the plane never
/// hits it, however close it runs.
std::optional<double> planeCrossing(const AnalyticShape& plane, const Eigen::Vector3d& origin,
                                    const Eigen::Vector3d& direction) {
  const double approach = plane.normal.dot(direction);
  if (approach == 0) return std::nullopt;
  return (plane.offset - plane.normal.dot(origin)) / approach;
}

/// As intersectInShape, with the ray and the normal in the frame. A plane needs no change of frame.
std::optional<SurfaceHit> intersect(const AnalyticShape& shape, const Eigen::Vector3d& origin,
                                    const Eigen::Vector3d& direction, double t_min, double t_max) {
  if (shape.type == Shape::Type::kPlane) {
    const std::optional<double> t = planeCrossing(shape, origin, direction);
    if (!t) return std::nullopt;
    ClosestHit closest(t_min, t_max);
    closest.offer(*t, shape.normal);
    return closest.hit();
  }
  std::optional<SurfaceHit> hit = intersectInShape(
      shape, shape.shape_from_frame * origin, shape.shape_from_frame.linear() * direction, t_min, t_max);
  if (hit) hit->normal = shape.frame_from_shape.linear() * hit->normal;
  return hit;
}

/// A surface's unit normal turned to face the ray that met it.
Eigen::Vector3d facingRay(const Eigen::Vector3d& normal, const Eigen::Vector3d& direction) {
  return normal.dot(direction) > 0 ? -normal : normal;
}

/// castStatic's rays against static planes alone, in double precision (a wheel's ray to the ground: Embree
/// took 400 instructions a ray, and rounded the ray to float).
void castAtPlanes(const std::vector<const AnalyticShape*>& planes,
                  const std::vector<Eigen::Vector3d>& origins, const std::vector<Eigen::Vector3d>& directions,
                  double max_range, std::vector<double>& ranges, std::vector<Eigen::Vector3d>* normals,
                  std::vector<double>* frictions) {
  ranges.assign(origins.size(), std::numeric_limits<double>::infinity());
  if (normals) normals->resize(origins.size());
  if (frictions) frictions->resize(origins.size());
  // Each wheel's ray to the ground, every substep: the crossing alone, without intersect's hit.
  for (size_t i = 0; i < origins.size(); ++i) {
    for (const AnalyticShape* plane : planes) {
      const std::optional<double> t = planeCrossing(*plane, origins[i], directions[i]);
      if (!t || !(*t >= 0 && *t <= max_range && *t < ranges[i])) continue;  // NaN too: a ray not finite
      ranges[i] = *t;
      if (normals) (*normals)[i] = facingRay(plane->normal, directions[i]);
      if (frictions) (*frictions)[i] = plane->mu;
    }
  }
}

/// The geometries hit by rays that must pass through: a moving body is a whole instance of the top scene; a
/// static body is up to two geometries inside the static instance.
struct IgnoredBody {
  unsigned instance = RTC_INVALID_GEOMETRY_ID;
  bool whole_instance = false;
  unsigned triangles = RTC_INVALID_GEOMETRY_ID;
  unsigned analytic = RTC_INVALID_GEOMETRY_ID;

  bool contains(unsigned hit_instance, unsigned hit_geometry) const {
    return hit_instance == instance &&
           (whole_instance || hit_geometry == triangles || hit_geometry == analytic);
  }
};

/// Embree hands the context pointer to every callback, so extending it carries the ignored body to them.
struct CastContext {
  RTCIntersectContext embree;  // first member: a pointer to it is a pointer to the CastContext
  IgnoredBody ignored;
};

const IgnoredBody& ignoredBody(const RTCIntersectContext* context) {
  return reinterpret_cast<const CastContext*>(context)->ignored;
}

/// Intersection filter on the context: rejects candidate triangle hits on the ignored body.
void skipIgnoredBody(const RTCFilterFunctionNArguments* args) {
  const IgnoredBody& ignored = ignoredBody(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == -1 &&
        ignored.contains(RTCHitN_instID(args->hit, args->N, i, 0), RTCHitN_geomID(args->hit, args->N, i)))
      args->valid[i] = 0;
  }
}

void analyticBounds(const RTCBoundsFunctionArguments* args) {
  *args->bounds_o = static_cast<const AnalyticShape*>(args->geometryUserPtr)[args->primID].bounds;
}

/// Embree's ray arrives in the frame of the instanced scene (the body frame for moving bodies).
void intersectAnalytic(const RTCIntersectFunctionNArguments* args) {
  const unsigned instance = args->context->instID[0];
  // Checked here rather than through rtcFilterIntersection: skips the whole primitive at once.
  if (ignoredBody(args->context).contains(instance, args->geomID)) return;
  const AnalyticShape& shape = static_cast<const AnalyticShape*>(args->geometryUserPtr)[args->primID];
  const unsigned n = args->N;
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, n);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, n);
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const Eigen::Vector3d origin(RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i),
                                 RTCRayN_org_z(rays, n, i));
    const Eigen::Vector3d direction(RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i),
                                    RTCRayN_dir_z(rays, n, i));
    const std::optional<SurfaceHit> hit =
        intersect(shape, origin, direction, RTCRayN_tnear(rays, n, i), RTCRayN_tfar(rays, n, i));
    if (!hit) continue;
    // Rounding to float cannot exceed the old tfar: it is a float no smaller than hit->t.
    RTCRayN_tfar(rays, n, i) = static_cast<float>(hit->t);
    const Eigen::Vector3f normal = hit->normal.cast<float>();
    RTCHitN_Ng_x(hits, n, i) = normal.x();
    RTCHitN_Ng_y(hits, n, i) = normal.y();
    RTCHitN_Ng_z(hits, n, i) = normal.z();
    RTCHitN_u(hits, n, i) = 0;
    RTCHitN_v(hits, n, i) = 0;
    RTCHitN_primID(hits, n, i) = args->primID;
    RTCHitN_geomID(hits, n, i) = args->geomID;
    RTCHitN_instID(hits, n, i, 0) = instance;
  }
}

/// Bounds in float that surely contain the double-precision box center +- half_extent.
RTCBounds paddedBounds(const Eigen::Vector3d& center, const Eigen::Vector3d& half_extent) {
  const Eigen::Vector3d pad = Eigen::Vector3d::Constant(1e-4) + 1e-6 * (center.cwiseAbs() + half_extent);
  const Eigen::Vector3f lower = (center - half_extent - pad).cast<float>();
  const Eigen::Vector3f upper = (center + half_extent + pad).cast<float>();
  RTCBounds bounds;
  bounds.lower_x = lower.x();
  bounds.lower_y = lower.y();
  bounds.lower_z = lower.z();
  bounds.upper_x = upper.x();
  bounds.upper_y = upper.y();
  bounds.upper_z = upper.z();
  return bounds;
}

AnalyticShape analyticShape(const Shape& shape, const Eigen::Isometry3d& frame_from_shape) {
  const Eigen::Matrix3d& rotation = frame_from_shape.linear();
  const Eigen::Vector3d normal = rotation * shape.plane_normal.normalized();
  AnalyticShape analytic{shape.type,   frame_from_shape, frame_from_shape.inverse(),
                         shape.radius, shape.length / 2, normal,
                         normal.dot(frame_from_shape.translation()), RTCBounds{}, 1.0};
  Eigen::Vector3d half_extent;
  if (shape.type == Shape::Type::kSphere) {
    half_extent.setConstant(shape.radius);
  } else if (shape.type == Shape::Type::kCylinder) {
    // A disc of radius r with unit normal a reaches r * sqrt(1 - a_i^2) along axis i.
    const Eigen::Vector3d axis = rotation.col(2);
    const Eigen::Vector3d disc = (1 - axis.array().square()).max(0).sqrt() * shape.radius;
    half_extent = axis.cwiseAbs() * analytic.half_length + disc;
  } else {
    half_extent = (1 - normal.array().square()).max(0).sqrt() * kPlaneRadius;
  }
  analytic.bounds = paddedBounds(frame_from_shape.translation(), half_extent);
  return analytic;
}

struct Triangles {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<unsigned, 3>> indices;
};

void appendBox(const Eigen::Vector3d& size, const Eigen::Isometry3d& frame_from_box, Triangles& triangles) {
  const auto base = static_cast<unsigned>(triangles.vertices.size());
  for (unsigned corner = 0; corner < 8; ++corner) {  // bits 0, 1, 2 select the +x, +y, +z side
    const Eigen::Vector3d sign((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
    triangles.vertices.push_back((frame_from_box * sign.cwiseProduct(size / 2)).cast<float>());
  }
  // Each face is a cycle of four corners, split into two triangles (Embree's triangles are two-sided).
  constexpr std::array<std::array<unsigned, 4>, 6> kFaces{
      {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}}};
  for (const auto& face : kFaces) {
    triangles.indices.push_back({base + face[0], base + face[1], base + face[2]});
    triangles.indices.push_back({base + face[0], base + face[2], base + face[3]});
  }
}

void appendMesh(const TriangleMesh& mesh, const Eigen::Isometry3d& frame_from_mesh, Triangles& triangles) {
  const auto base = static_cast<unsigned>(triangles.vertices.size());
  for (const Eigen::Vector3d& vertex : mesh.vertices)
    triangles.vertices.push_back((frame_from_mesh * vertex).cast<float>());
  for (const auto& triangle : mesh.triangles)
    triangles.indices.push_back({base + triangle[0], base + triangle[1], base + triangle[2]});
}

/// Robust: watertight triangle tests, so no ray slips through the shared edge of two triangles (without it,
/// about 1 lidar ray in 17 M did, off by up to 0.8 m; it costs about 10 % of the casting time).
/// Context filter: allowed for every scene, so cast() can ignore a body; the flag alone costs nothing
/// measurable.
SceneHandle newScene(RTCDevice device, RTCBuildQuality quality, RTCSceneFlags extra_flags) {
  SceneHandle scene(rtcNewScene(device));
  rtcSetSceneFlags(scene.get(),
                   static_cast<RTCSceneFlags>(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION |
                                              extra_flags));
  rtcSetSceneBuildQuality(scene.get(), quality);
  return scene;
}

/// Also commits the instance, so set anything else on it first.
void setInstanceTransform(RTCGeometry instance, const Eigen::Isometry3d& pose) {
  const Eigen::Matrix<float, 3, 4> transform = pose.matrix().topRows<3>().cast<float>();  // column-major
  rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform.data());
  rtcCommitGeometry(instance);
}

struct Body {
  bool is_static = false;
  /// The user data of the analytic geometry: never resized once attached.
  std::vector<AnalyticShape> analytic_shapes;
  /// Each shape's first triangle in the triangle geometry, with its collision's mu, in order.
  std::vector<std::pair<unsigned, double>> triangle_mu;
  /// Geometry ids in the body's own scene (moving) or in the static scene (static).
  unsigned triangles_id = RTC_INVALID_GEOMETRY_ID;
  unsigned analytic_id = RTC_INVALID_GEOMETRY_ID;
  // Moving bodies only.
  SceneHandle scene;
  GeometryHandle instance;  ///< of `scene`, in the top scene
  unsigned instance_id = RTC_INVALID_GEOMETRY_ID;
  unsigned mask = kSharedMask;  ///< the instance's geometry mask
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  bool pose_changed = false;
  bool hidden = false;  ///< its pose is not finite (its physics diverged): rays pass it by
};

}  // namespace

// The top scene instances the static scene once and each moving body's scene once, so commit() rebuilds a
// tree over a few instances only; the static scene is rebuilt only when static bodies come or go.
struct RayCaster::Impl {
  Impl();
  /// Throws std::runtime_error naming `operation` if Embree reported an error since the last check.
  void throwOnError(const std::string& operation);
  /// Attaches the shapes (placed in the scene's frame by frame_from_body) to `scene` and records their ids.
  void attachShapes(const std::vector<Collision>& shapes, const Eigen::Isometry3d& frame_from_body,
                    RTCScene scene, Body& body);
  Body& body(BodyId id, const char* operation) const;
  /// Sets static_planes from the static bodies.
  void findStaticPlanes();
  /// The mu of the static shape a ray hit: primitive `primitive` of geometry `geometry` of the static scene.
  double staticFriction(unsigned geometry, unsigned primitive) const;

  std::string embree_error;  // outlives the device, which reports into it
  DeviceHandle device;
  SceneHandle statics;  ///< every static body's shapes, in world coordinates
  SceneHandle top;      ///< the static scene once plus one instance per moving body
  unsigned statics_instance_id = RTC_INVALID_GEOMETRY_ID;
  std::vector<std::unique_ptr<Body>> bodies;  ///< indexed by BodyId; null once removed
  std::vector<const Body*> static_owners;     ///< by geometry id in `statics`: the body it belongs to
  MaskPool masks;  ///< for moving bodies
  bool statics_changed = false;
  /// When every static shape is a plane (empty.world's ground): them, which castStatic meets without Embree.
  std::optional<std::vector<const AnalyticShape*>> static_planes;
  bool bodies_added_or_removed = false;  ///< Embree's scenes are not castable until committed
  bool top_changed = false;
};

// One build thread. The top tree is rebuilt at every step that casts, and each build woke Embree's TBB
// workers, which then spun on the other core for the next one, taking it from the pool and the node's other
// processes (docs/performance.md). Static shapes are built once, at spawn or when the world loads, on the
// calling thread.
RayCaster::Impl::Impl() : device(rtcNewDevice("threads=1")) {
  if (!device) throw std::runtime_error("RayCaster: cannot create an Embree device");
  rtcSetDeviceErrorFunction(
      device.get(),
      [](void* error, RTCError, const char* message) { *static_cast<std::string*>(error) = message; },
      &embree_error);
  // Static shapes are built once, so the slowest, best tree pays off.
  statics = newScene(device.get(), RTC_BUILD_QUALITY_HIGH, RTC_SCENE_FLAG_NONE);
  rtcCommitScene(statics.get());
  // The top tree is rebuilt at every step that scans. Embree's low quality builds a two-level structure,
  // which over instances alone took twice as long to build as the medium one, and cast no faster.
  top = newScene(device.get(), RTC_BUILD_QUALITY_MEDIUM, RTC_SCENE_FLAG_DYNAMIC);
  const GeometryHandle instance(rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_INSTANCE));
  rtcSetGeometryInstancedScene(instance.get(), statics.get());
  rtcSetGeometryMask(instance.get(), kSharedMask);
  setInstanceTransform(instance.get(), Eigen::Isometry3d::Identity());
  statics_instance_id = rtcAttachGeometry(top.get(), instance.get());
  rtcCommitScene(top.get());
  throwOnError("RayCaster: creating the scenes");
}

void RayCaster::Impl::throwOnError(const std::string& operation) {
  if (rtcGetDeviceError(device.get()) != RTC_ERROR_NONE)
    throw std::runtime_error(operation + ": Embree: " + embree_error);
}

void RayCaster::Impl::attachShapes(const std::vector<Collision>& shapes,
                                   const Eigen::Isometry3d& frame_from_body, RTCScene scene, Body& body) {
  Triangles triangles;
  for (const Collision& collision : shapes) {
    const Eigen::Isometry3d frame_from_shape = frame_from_body * collision.origin;
    const Shape& shape = collision.shape;
    switch (shape.type) {
      case Shape::Type::kBox:
        body.triangle_mu.emplace_back(triangles.indices.size(), collision.mu);
        appendBox(shape.box_size, frame_from_shape, triangles);
        break;
      case Shape::Type::kMesh:
        body.triangle_mu.emplace_back(triangles.indices.size(), collision.mu);
        if (shape.mesh) appendMesh(*shape.mesh, frame_from_shape, triangles);
        break;
      case Shape::Type::kSphere:
      case Shape::Type::kCylinder:
      case Shape::Type::kPlane:
        body.analytic_shapes.push_back(analyticShape(shape, frame_from_shape));
        body.analytic_shapes.back().mu = collision.mu;
        break;
    }
  }

  if (!triangles.indices.empty()) {
    const GeometryHandle geometry(rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0,
                                                                 RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                                 triangles.vertices.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0,
                                                                   RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                                   triangles.indices.size()));
    throwOnError("RayCaster::addBody: allocating triangles");
    for (const Eigen::Vector3f& vertex : triangles.vertices)
      vertices = std::copy_n(vertex.data(), 3, vertices);
    for (const auto& triangle : triangles.indices) indices = std::copy_n(triangle.data(), 3, indices);
    rtcCommitGeometry(geometry.get());
    body.triangles_id = rtcAttachGeometry(scene, geometry.get());
  }

  if (!body.analytic_shapes.empty()) {
    const GeometryHandle geometry(rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_USER));
    rtcSetGeometryUserPrimitiveCount(geometry.get(), static_cast<unsigned>(body.analytic_shapes.size()));
    rtcSetGeometryUserData(geometry.get(), body.analytic_shapes.data());
    rtcSetGeometryBoundsFunction(geometry.get(), analyticBounds, nullptr);
    rtcSetGeometryIntersectFunction(geometry.get(), intersectAnalytic);
    rtcCommitGeometry(geometry.get());
    body.analytic_id = rtcAttachGeometry(scene, geometry.get());
  }
  throwOnError("RayCaster::addBody");
}

Body& RayCaster::Impl::body(BodyId id, const char* operation) const {
  if (id < 0 || static_cast<size_t>(id) >= bodies.size() || !bodies[id])
    throw std::invalid_argument(std::string(operation) + ": unknown body " + std::to_string(id));
  return *bodies[id];
}

RayCaster::RayCaster() : impl_(std::make_unique<Impl>()) {}
RayCaster::~RayCaster() = default;
RayCaster::RayCaster(RayCaster&&) noexcept = default;
RayCaster& RayCaster::operator=(RayCaster&&) noexcept = default;

BodyId RayCaster::addBody(const std::vector<Collision>& shapes, const Eigen::Isometry3d& pose,
                          bool is_static) {
  Impl& impl = *impl_;
  auto body = std::make_unique<Body>();
  body->is_static = is_static;
  if (is_static) {
    impl.attachShapes(shapes, pose, impl.statics.get(), *body);
    for (const unsigned geometry : {body->triangles_id, body->analytic_id}) {
      if (geometry == RTC_INVALID_GEOMETRY_ID) continue;
      if (impl.static_owners.size() <= geometry) impl.static_owners.resize(geometry + 1);
      impl.static_owners[geometry] = body.get();
    }
    impl.statics_changed = true;
  } else {
    // Shapes in the body frame, built once; commit() only moves the instance.
    body->scene = newScene(impl.device.get(), RTC_BUILD_QUALITY_HIGH, RTC_SCENE_FLAG_NONE);
    impl.attachShapes(shapes, Eigen::Isometry3d::Identity(), body->scene.get(), *body);
    rtcCommitScene(body->scene.get());
    body->instance.reset(rtcNewGeometry(impl.device.get(), RTC_GEOMETRY_TYPE_INSTANCE));
    rtcSetGeometryInstancedScene(body->instance.get(), body->scene.get());
    body->mask = impl.masks.take();
    rtcSetGeometryMask(body->instance.get(), body->mask);
    setInstanceTransform(body->instance.get(), pose);
    body->pose = pose;
    body->instance_id = rtcAttachGeometry(impl.top.get(), body->instance.get());
    impl.throwOnError("RayCaster::addBody");
  }
  impl.bodies.push_back(std::move(body));
  impl.bodies_added_or_removed = true;
  impl.top_changed = true;
  return static_cast<BodyId>(impl.bodies.size() - 1);
}

void RayCaster::removeBody(BodyId id) {
  Impl& impl = *impl_;
  const Body& body = impl.body(id, "RayCaster::removeBody");
  if (body.is_static) {
    for (const unsigned geometry : {body.triangles_id, body.analytic_id}) {
      if (geometry == RTC_INVALID_GEOMETRY_ID) continue;
      rtcDetachGeometry(impl.statics.get(), geometry);
      impl.static_owners[geometry] = nullptr;
    }
    impl.statics_changed = true;
  } else {
    rtcDetachGeometry(impl.top.get(), body.instance_id);
    impl.masks.give(body.mask);
  }
  impl.bodies[id].reset();
  impl.bodies_added_or_removed = true;
  impl.top_changed = true;
}

void RayCaster::setPose(BodyId id, const Eigen::Isometry3d& pose) {
  Body& body = impl_->body(id, "RayCaster::setPose");
  if (body.is_static)
    throw std::invalid_argument("RayCaster::setPose: body " + std::to_string(id) + " is static");
  body.pose = pose;
  body.pose_changed = true;
  impl_->top_changed = true;
}

double RayCaster::Impl::staticFriction(unsigned geometry, unsigned primitive) const {
  const Body& owner = *static_owners.at(geometry);
  if (geometry == owner.analytic_id) return owner.analytic_shapes.at(primitive).mu;
  // The last shape whose first triangle is not past the one hit.
  const auto past = [](unsigned triangle, const auto& shape) { return triangle < shape.first; };
  const auto shape = std::upper_bound(owner.triangle_mu.begin(), owner.triangle_mu.end(), primitive, past);
  return std::prev(shape)->second;
}

void RayCaster::Impl::findStaticPlanes() {
  static_planes.emplace();
  for (const auto& body : bodies) {
    if (!body || !body->is_static) continue;
    if (body->triangles_id != RTC_INVALID_GEOMETRY_ID) {
      static_planes.reset();
      return;
    }
    for (const AnalyticShape& shape : body->analytic_shapes) {
      if (shape.type != Shape::Type::kPlane) {
        static_planes.reset();
        return;
      }
      static_planes->push_back(&shape);
    }
  }
}

void RayCaster::commit() {
  Impl& impl = *impl_;
  if (!impl.top_changed) return;
  if (impl.statics_changed) {
    rtcCommitScene(impl.statics.get());
    // The instance's bounds follow the static scene's.
    rtcCommitGeometry(rtcGetGeometry(impl.top.get(), impl.statics_instance_id));
    impl.findStaticPlanes();
  }
  for (const auto& body : impl.bodies) {
    if (!body || !body->pose_changed) continue;
    body->pose_changed = false;
    // Embree would build its tree around NaN bounds.
    const bool finite = body->pose.matrix().allFinite();
    if (finite == body->hidden) {
      body->hidden = !finite;
      finite ? rtcEnableGeometry(body->instance.get()) : rtcDisableGeometry(body->instance.get());
    }
    if (finite) setInstanceTransform(body->instance.get(), body->pose);
  }
  rtcCommitScene(impl.top.get());
  impl.throwOnError("RayCaster::commit");
  // Written only when they change: a commit of moved bodies alone may run beside castStatic, which reads
  // them.
  if (impl.statics_changed) impl.statics_changed = false;
  if (impl.bodies_added_or_removed) impl.bodies_added_or_removed = false;
  impl.top_changed = false;
}

/// A unit direction's component below float's resolution (a robot tilted by 1e-15 rad as it settles), as 0.
/// Embree's coherent traversal bounds a packet by the reciprocals of its directions, and a packet whose
/// reciprocals span 1e7 to 1e14 culled walls it should hit (Lidar.ATiltedLidarSeesTheWallsWhereTheyAre).
namespace {
float hairToZero(float component) { return std::abs(component) < 1e-7f ? 0.0f : component; }
}  // namespace

void RayCaster::cast(const Eigen::Vector3d& origin, const std::vector<Eigen::Vector3f>& directions,
                     double max_range, BodyId ignore, std::vector<double>& ranges) const {
  const Impl& impl = *impl_;
  if (impl.bodies_added_or_removed)
    throw std::logic_error("RayCaster::cast: bodies were added or removed since the last commit()");

  CastContext context;
  rtcInitIntersectContext(&context.embree);
  // A scan's rays share their origin: coherent traversal casts them 3x faster (but see hairToZero).
  context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  unsigned ray_mask = ~0u;
  if (ignore != kNoBody) {
    // A body with a mask of its own is skipped by the ray mask at no cost. The others (static bodies, and
    // moving ones once the MaskPool ran out) are skipped by a filter on the context. The filter runs on every
    // candidate hit, and a sensor inside the ignored body makes one per ray: a lidar on a robot cast 1.5x
    // slower so.
    const Body& body = impl.body(ignore, "RayCaster::cast");
    if (body.mask != kSharedMask) {
      ray_mask = ~body.mask;
    } else {
      context.ignored =
          body.is_static ? IgnoredBody{impl.statics_instance_id, false, body.triangles_id, body.analytic_id}
                         : IgnoredBody{body.instance_id, true};
      context.embree.filter = skipIgnoredBody;
    }
  }

  ranges.resize(directions.size());
  // Embree aborts the process on a ray that is not finite (a sensor on a body whose physics diverged).
  if (!origin.allFinite()) {
    std::fill(ranges.begin(), ranges.end(), std::numeric_limits<double>::infinity());
    return;
  }
  const Eigen::Vector3f ray_origin = origin.cast<float>();
  const auto ray_length = static_cast<float>(max_range);
  RTCRayHit16 packet;
  alignas(64) std::array<int, kPacketSize> valid;  // Embree wants it aligned like the packet
  for (size_t first = 0; first < directions.size(); first += kPacketSize) {
    const size_t count = std::min(kPacketSize, directions.size() - first);
    for (size_t lane = 0; lane < kPacketSize; ++lane) {
      const Eigen::Vector3f& direction = directions[first + std::min(lane, count - 1)];
      valid[lane] = lane < count && direction.allFinite() ? -1 : 0;
      packet.ray.org_x[lane] = ray_origin.x();
      packet.ray.org_y[lane] = ray_origin.y();
      packet.ray.org_z[lane] = ray_origin.z();
      packet.ray.dir_x[lane] = hairToZero(direction.x());
      packet.ray.dir_y[lane] = hairToZero(direction.y());
      packet.ray.dir_z[lane] = hairToZero(direction.z());
      packet.ray.tnear[lane] = 0;
      packet.ray.tfar[lane] = ray_length;
      packet.ray.time[lane] = 0;
      packet.ray.mask[lane] = ray_mask;
      packet.ray.id[lane] = static_cast<unsigned>(lane);
      packet.ray.flags[lane] = 0;
      packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid.data(), impl.top.get(), &context.embree, &packet);
    for (size_t lane = 0; lane < count; ++lane) {  // an invalid lane keeps its geomID
      ranges[first + lane] = packet.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID
                                 ? std::numeric_limits<double>::infinity()
                                 : static_cast<double>(packet.ray.tfar[lane]);
    }
  }
}

void RayCaster::castStatic(const std::vector<Eigen::Vector3d>& origins,
                           const std::vector<Eigen::Vector3d>& directions, double max_range,
                           std::vector<double>& ranges, std::vector<Eigen::Vector3d>* normals,
                           std::vector<double>* frictions) const {
  const Impl& impl = *impl_;
  if (impl.statics_changed)
    throw std::logic_error("RayCaster::castStatic: static bodies changed since the last commit()");
  if (impl.static_planes) {
    castAtPlanes(*impl.static_planes, origins, directions, max_range, ranges, normals, frictions);
    return;
  }
  CastContext context;
  rtcInitIntersectContext(&context.embree);
  ranges.resize(origins.size());
  if (normals) normals->resize(origins.size());
  if (frictions) frictions->resize(origins.size());
  for (size_t i = 0; i < origins.size(); ++i) {
    ranges[i] = std::numeric_limits<double>::infinity();
    if (!origins[i].allFinite() || !directions[i].allFinite()) continue;  // Embree aborts on it
    RTCRayHit ray{};
    ray.ray.org_x = static_cast<float>(origins[i].x());
    ray.ray.org_y = static_cast<float>(origins[i].y());
    ray.ray.org_z = static_cast<float>(origins[i].z());
    ray.ray.dir_x = static_cast<float>(directions[i].x());
    ray.ray.dir_y = static_cast<float>(directions[i].y());
    ray.ray.dir_z = static_cast<float>(directions[i].z());
    ray.ray.tnear = 0;
    ray.ray.tfar = static_cast<float>(max_range);
    ray.ray.mask = ~0u;
    ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl.statics.get(), &context.embree, &ray);
    ranges[i] = ray.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<double>::infinity()
                                                          : static_cast<double>(ray.ray.tfar);
    if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    if (frictions) (*frictions)[i] = impl.staticFriction(ray.hit.geomID, ray.hit.primID);
    if (!normals) continue;
    (*normals)[i] =
        facingRay(Eigen::Vector3d(ray.hit.Ng_x, ray.hit.Ng_y, ray.hit.Ng_z).normalized(), directions[i]);
  }
}

}  // namespace bullet_sim
