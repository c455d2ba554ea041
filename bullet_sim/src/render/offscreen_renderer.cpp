#include "bullet_sim/render/offscreen_renderer.h"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace bullet_sim {

namespace {

// Faces meeting at less than this angle share their corners' normals (a smooth cylinder); sharper edges
// (a box's) stay sharp.
constexpr double kCreaseAngle = 40 * M_PI / 180;
constexpr int kMaxImageSide = 16384;  // [px], llvmpipe's largest render target
// Pushes filled triangles back in depth, so points and lines lying on a surface (lidar hits on a wall, the
// grid on the ground) are drawn over it: `factor` scales with the triangle's depth slope, `units` are the
// depth buffer's smallest steps.
constexpr GLfloat kSurfaceOffsetFactor = 1, kSurfaceOffsetUnits = 4;
constexpr int kFloatsPerCorner = 6;  // position, normal

/// Per triangle corner, its position and normal, ready for glDrawArrays. A triangle wound the wrong way (as
/// CAD exports have) gets an inward normal; two-sided lighting lights it right, since the camera then sees
/// its back.
std::vector<float> cornerAttributes(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> area_normals, unit_normals;  // per triangle; |area normal| = 2 * area
  std::vector<std::vector<int>> triangles_at(mesh.vertices.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& [a, b, c] = mesh.triangles[t];
    const Eigen::Vector3d normal =
        (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
    area_normals.push_back(normal);
    unit_normals.push_back(normal.norm() > 0 ? normal.normalized() : Eigen::Vector3d::Zero());
    for (const int vertex : mesh.triangles[t]) triangles_at[vertex].push_back(static_cast<int>(t));
  }
  const double crease = std::cos(kCreaseAngle);
  std::vector<float> attributes;
  attributes.reserve(mesh.triangles.size() * 3 * kFloatsPerCorner);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const int vertex : mesh.triangles[t]) {
      Eigen::Vector3d smooth = Eigen::Vector3d::Zero();
      for (const int other : triangles_at[vertex]) {
        if (unit_normals[other].dot(unit_normals[t]) >= crease) smooth += area_normals[other];
      }
      const Eigen::Vector3f position = mesh.vertices[vertex].cast<float>();
      const Eigen::Vector3f normal =
          (smooth.norm() > 0 ? smooth.normalized() : unit_normals[t]).cast<float>();
      attributes.insert(attributes.end(),
                        {position.x(), position.y(), position.z(), normal.x(), normal.y(), normal.z()});
    }
  }
  return attributes;
}

void setColour(const Eigen::Vector4d& rgba) { glColor4d(rgba[0], rgba[1], rgba[2], rgba[3]); }

void drawVertices(GLenum mode, const std::vector<Eigen::Vector3d>& points) {
  glVertexPointer(3, GL_DOUBLE, sizeof(Eigen::Vector3d), points.data());
  glDrawArrays(mode, 0, static_cast<GLsizei>(points.size()));
}

/// Grid lines every Scene::kGridSpacing on z = 0, around the point in the middle of the view.
std::vector<Eigen::Vector3d> gridLines(const Camera& camera) {
  const Eigen::Vector2d middle =
      camera.projection == Camera::Projection::kOrthographic ? camera.centre : camera.target.head<2>();
  const double spacing = Scene::kGridSpacing;
  const Eigen::Vector2d origin = (middle / spacing).array().round() * spacing;
  const int lines = static_cast<int>(Scene::kGridHalfExtent / spacing);
  const double half = lines * spacing;
  std::vector<Eigen::Vector3d> vertices;
  for (int i = -lines; i <= lines; ++i) {
    const double offset = i * spacing;
    vertices.emplace_back(origin.x() + offset, origin.y() - half, 0);
    vertices.emplace_back(origin.x() + offset, origin.y() + half, 0);
    vertices.emplace_back(origin.x() - half, origin.y() + offset, 0);
    vertices.emplace_back(origin.x() + half, origin.y() + offset, 0);
  }
  return vertices;
}

}  // namespace

/// An OSMesa context and the meshes uploaded to it.
class OffscreenRenderer::Context {
 public:
  Context() : context_(OSMesaCreateContextExt(OSMESA_RGBA, /*depthBits=*/24, 0, 0, nullptr)) {
    if (!context_) {
      throw std::runtime_error(
          "OffscreenRenderer: OSMesa could not create an OpenGL context; check that libosmesa6 is installed "
          "and that MESA_* or GALLIUM_DRIVER environment variables do not select an unavailable driver");
    }
  }

  ~Context() {
    if (OSMesaGetCurrentContext() == context_) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(context_);  // frees the buffers uploaded to it
  }

  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  Image render(const Scene& scene, int width, int height, std::vector<float>* depth) {
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide) {
      throw std::invalid_argument("OffscreenRenderer: cannot render " + std::to_string(width) + "x" +
                                  std::to_string(height) + " pixels; each side must be 1 to " +
                                  std::to_string(kMaxImageSide));
    }
    // OSMesa renders into a frame buffer of its own for each size, kept across renders, and copies it into
    // `pixels_` at glFinish. `pixels_` lives as long as the context, which may copy into it whenever it is
    // flushed, e.g. when another context becomes current.
    pixels_.resize(static_cast<size_t>(width) * height * 4);
    if (!OSMesaMakeCurrent(context_, pixels_.data(), GL_UNSIGNED_BYTE, width, height)) {
      throw std::runtime_error("OffscreenRenderer: OSMesa could not render into a " + std::to_string(width) +
                               "x" + std::to_string(height) + " buffer");
    }
    OSMesaPixelStore(OSMESA_Y_UP, 0);  // first row in memory = top row of the picture
    if (!initialised_) initialise();

    glViewport(0, 0, width, height);
    glClearColor(scene.background[0], scene.background[1], scene.background[2], scene.background[3]);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    const Eigen::Matrix4d projection = scene.camera.projectionMatrix(static_cast<double>(width) / height);
    const Eigen::Matrix4d view = scene.camera.viewMatrix();
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(projection.data());
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixd(view.data());
    setLight(scene.lighting);

    drawMeshes(scene, view, /*translucent=*/false);
    if (scene.outline_step > 0) drawOutlines(scene, width, height);
    glLoadMatrixd(view.data());
    if (scene.ground_grid) {
      setColour(scene.grid_rgba);
      glLineWidth(1);
      drawVertices(GL_LINES, gridLines(scene.camera));
    }
    for (const Polyline& line : scene.polylines) {
      setColour(line.rgba);
      glLineWidth(static_cast<GLfloat>(line.width));
      drawVertices(GL_LINE_STRIP, line.points);
    }
    drawPoints(scene, /*overlay=*/false);
    drawMeshes(scene, view, /*translucent=*/true);
    glLoadMatrixd(view.data());
    glDisable(GL_DEPTH_TEST);
    drawPoints(scene, /*overlay=*/true);
    glEnable(GL_DEPTH_TEST);

    glFinish();
    if (depth) readDepth(scene.camera, width, height, *depth);
    forgetDeadMeshes();
    return Image{width, height, pixels_};
  }

 private:
  struct GpuMesh {
    std::weak_ptr<const TriangleMesh> source;  ///< expired once nobody draws it any more
    GLuint buffer = 0;
    GLsizei corners = 0;
  };

  void initialise() {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_LIGHT0);
    // Meshes with inconsistent winding (common in CAD exports) are lit on whichever side faces the camera.
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    const GLfloat no_global_ambient[] = {0, 0, 0, 1};
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, no_global_ambient);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glShadeModel(GL_SMOOTH);
    glPolygonOffset(kSurfaceOffsetFactor, kSurfaceOffsetUnits);
    // See-through colours mix; the picture's alpha stays that of what lies behind (opaque).
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glEnableClientState(GL_VERTEX_ARRAY);
    initialised_ = true;
  }

  /// The depth buffer as distances along the view axis [m], rows top first; +inf where nothing was drawn.
  static void readDepth(const Camera& camera, int width, int height, std::vector<float>& depth) {
    depth.resize(static_cast<size_t>(width) * height);
    glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    for (float& value : depth) {
      // [0, 1]; 1 is the far plane, where nothing was drawn
      value = value >= 1 ? std::numeric_limits<float>::infinity() : static_cast<float>(camera.viewDepth(value));
    }
    // OpenGL reads the bottom row first.
    for (int row = 0; row < height / 2; ++row) {
      std::swap_ranges(depth.begin() + static_cast<long>(row) * width,
                       depth.begin() + static_cast<long>(row + 1) * width,
                       depth.begin() + static_cast<long>(height - 1 - row) * width);
    }
  }

  /// Darkens the pixels beside a surface that is outline_step nearer than they are: the edges of what stands
  /// out from what lies behind it, whatever their colours. Drawn as window-space points over the meshes.
  static void drawOutlines(const Scene& scene, int width, int height) {
    std::vector<float> depth;
    readDepth(scene.camera, width, height, depth);
    std::vector<Eigen::Vector2d> outline;  // window coordinates, bottom row first
    const auto nearer = [&](int x, int y, float here) {
      return x >= 0 && y >= 0 && x < width && y < height &&
             depth[static_cast<size_t>(y) * width + x] < here - scene.outline_step;
    };
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const float here = depth[static_cast<size_t>(y) * width + x];
        if (nearer(x - 1, y, here) || nearer(x + 1, y, here) || nearer(x, y - 1, here) ||
            nearer(x, y + 1, here))
          outline.emplace_back(x + 0.5, height - 1 - y + 0.5);
      }
    }
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glOrtho(0, width, 0, height, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glDisable(GL_DEPTH_TEST);
    setColour(scene.outline_rgba);
    glPointSize(1);
    glVertexPointer(2, GL_DOUBLE, sizeof(Eigen::Vector2d), outline.data());
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(outline.size()));
    glEnable(GL_DEPTH_TEST);
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
  }

  /// Call with the view matrix loaded: GL fixes the light's direction in eye coordinates then.
  static void setLight(const Lighting& lighting) {
    const Eigen::Vector3f towards_light = -lighting.direction.normalized().cast<float>();
    const GLfloat position[] = {towards_light.x(), towards_light.y(), towards_light.z(), 0};
    const auto ambient = static_cast<GLfloat>(lighting.ambient);
    const auto diffuse = static_cast<GLfloat>(lighting.diffuse);
    const GLfloat ambient_rgba[] = {ambient, ambient, ambient, 1};
    const GLfloat diffuse_rgba[] = {diffuse, diffuse, diffuse, 1};
    const GLfloat no_specular[] = {0, 0, 0, 1};
    glLightfv(GL_LIGHT0, GL_POSITION, position);
    glLightfv(GL_LIGHT0, GL_AMBIENT, ambient_rgba);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse_rgba);
    glLightfv(GL_LIGHT0, GL_SPECULAR, no_specular);
  }

  /// Opaque meshes write depth. See-through ones (alpha < 1) blend over what is drawn before them, and only
  /// the nearest see-through surface of a pixel does, once: a depth-only pass finds it first.
  void drawMeshes(const Scene& scene, const Eigen::Matrix4d& view, bool translucent) {
    glEnable(GL_LIGHTING);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glEnableClientState(GL_NORMAL_ARRAY);
    if (translucent) {
      glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      drawMeshesOfKind(scene, view, translucent);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glEnable(GL_BLEND);
      glDepthMask(GL_FALSE);
    }
    drawMeshesOfKind(scene, view, translucent);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_LIGHTING);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
  }

  void drawMeshesOfKind(const Scene& scene, const Eigen::Matrix4d& view, bool translucent) {
    for (const SceneMesh& mesh : scene.meshes) {
      if (!mesh.mesh || (mesh.rgba[3] < 1) != translucent) continue;
      const GpuMesh& gpu = upload(mesh.mesh);
      const Eigen::Matrix4d model_view = view * mesh.pose.matrix();
      glLoadMatrixd(model_view.data());
      setColour(mesh.rgba);
      glBindBuffer(GL_ARRAY_BUFFER, gpu.buffer);
      glVertexPointer(3, GL_FLOAT, kFloatsPerCorner * sizeof(float), nullptr);
      glNormalPointer(GL_FLOAT, kFloatsPerCorner * sizeof(float),
                      reinterpret_cast<const void*>(3 * sizeof(float)));
      glDrawArrays(GL_TRIANGLES, 0, gpu.corners);
    }
  }

  static void drawPoints(const Scene& scene, bool overlay) {
    for (const PointSet& set : scene.point_sets) {
      if (set.overlay != overlay) continue;
      setColour(set.rgba);
      glPointSize(static_cast<GLfloat>(set.size));
      drawVertices(GL_POINTS, set.points);
    }
  }

  /// The mesh's buffer, uploaded on first use.
  const GpuMesh& upload(const std::shared_ptr<const TriangleMesh>& mesh) {
    GpuMesh& gpu = meshes_[mesh.get()];
    // A dead mesh's address can be reused by a new one: its weak pointer tells them apart.
    if (gpu.buffer != 0 && gpu.source.lock() == mesh) return gpu;
    if (gpu.buffer == 0) glGenBuffers(1, &gpu.buffer);
    const std::vector<float> attributes = cornerAttributes(*mesh);
    glBindBuffer(GL_ARRAY_BUFFER, gpu.buffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(attributes.size() * sizeof(float)),
                 attributes.data(), GL_STATIC_DRAW);
    gpu.source = mesh;
    gpu.corners = static_cast<GLsizei>(attributes.size() / kFloatsPerCorner);
    return gpu;
  }

  void forgetDeadMeshes() {
    for (auto it = meshes_.begin(); it != meshes_.end();) {
      if (it->second.source.expired()) {
        glDeleteBuffers(1, &it->second.buffer);
        it = meshes_.erase(it);
      } else {
        ++it;
      }
    }
  }

  OSMesaContext context_;
  std::vector<uint8_t> pixels_;  ///< RGBA, top row first
  bool initialised_ = false;
  std::unordered_map<const TriangleMesh*, GpuMesh> meshes_;
};

OffscreenRenderer::OffscreenRenderer() : context_(std::make_unique<Context>()) {}
OffscreenRenderer::~OffscreenRenderer() = default;
OffscreenRenderer::OffscreenRenderer(OffscreenRenderer&&) noexcept = default;
OffscreenRenderer& OffscreenRenderer::operator=(OffscreenRenderer&&) noexcept = default;

Image OffscreenRenderer::render(const Scene& scene, int width, int height, std::vector<float>* depth) {
  if (!context_) throw std::logic_error("OffscreenRenderer::render: this renderer was moved from");
  return context_->render(scene, width, height, depth);
}

}  // namespace bullet_sim
