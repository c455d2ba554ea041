#include "bullet_sim/render/offscreen_renderer.h"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "gpu_resources.h"

namespace bullet_sim {

namespace {

constexpr int kMaxImageSide = 16384;  // [px], llvmpipe's largest render target
// Pushes filled triangles back in depth, so points and lines lying on a surface (lidar hits on a wall, the
// grid on the ground) are drawn over it: `factor` scales with the triangle's depth slope, `units` are the
// depth buffer's smallest steps.
constexpr GLfloat kSurfaceOffsetFactor = 1, kSurfaceOffsetUnits = 4;
// Texels more transparent than this are not drawn at all (cut-outs such as leaves and fences).
constexpr GLfloat kTextureAlphaCut = 0.5f;

/// How a part of a mesh is drawn.
struct Look {
  Eigen::Vector4d rgba;
  const std::shared_ptr<const Texture>* texture = nullptr;  ///< nullptr: none
};

/// The look of a mesh part whose file material is `material` (nullptr: the file gives none), as the mesh's
/// paint says: its file's colour (white under a texture it gives no colour for) and texture, the mesh's
/// colour over the file's texture, or the mesh's colour alone.
Look lookOf(const SceneMesh& mesh, const MeshMaterial* material) {
  if (!material || mesh.paint == MeshPaint::kUniform) return {mesh.rgba};
  const auto* texture = material->texture ? &material->texture : nullptr;
  if (mesh.paint == MeshPaint::kTint) return {mesh.rgba, texture};
  return {material->rgba.value_or(texture ? Eigen::Vector4d::Ones() : mesh.rgba), texture};
}

/// The six planes (a, b, c, d: inside where a x + b y + c z + d >= 0, |(a, b, c)| = 1) of the volume a
/// projection * view matrix shows.
std::array<Eigen::Vector4d, 6> frustumPlanes(const Eigen::Matrix4d& clip) {
  std::array<Eigen::Vector4d, 6> planes;
  for (int axis = 0; axis < 3; ++axis) {
    planes[2 * axis] = clip.row(3).transpose() + clip.row(axis).transpose();
    planes[2 * axis + 1] = clip.row(3).transpose() - clip.row(axis).transpose();
  }
  for (Eigen::Vector4d& plane : planes) plane /= plane.head<3>().norm();
  return planes;
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

  /// Draws `scene`; the picture is then in `pixels_` (RGBA, top row first) and the depth in GL's buffer.
  void draw(const Scene& scene, int width, int height) {
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

    collectVisible(scene, projection * view, view);
    drawMeshes(view, /*translucent=*/false);
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
    drawMeshes(view, /*translucent=*/true);
    glLoadMatrixd(view.data());
    glDisable(GL_DEPTH_TEST);
    drawPoints(scene, /*overlay=*/true);
    glEnable(GL_DEPTH_TEST);

    glFinish();
    gpu_.forgetDead();
  }

  const std::vector<uint8_t>& pixels() const { return pixels_; }

  /// The depth buffer as distances along the view axis [m], rows top first; +inf where nothing was drawn.
  static void readDepth(const Camera& camera, int width, int height, std::vector<float>& depth) {
    const size_t pixels = static_cast<size_t>(width) * height;
    depth.resize(pixels);
    // GL reads the bottom row first; Mesa's pack inversion (in every Mesa driver) reads the top row first.
    glPixelStorei(GL_PACK_INVERT_MESA, GL_TRUE);
    glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    glPixelStorei(GL_PACK_INVERT_MESA, GL_FALSE);
    // Camera::viewDepth for the whole buffer: (p + q w) / (r + s w) of each value w in [0, 1]. 1 is the far
    // plane, where nothing was drawn: there floor(w) = 1 makes the denominator 0 and the depth +inf (as
    // p + q > 0). One arithmetic expression, so that Eigen converts four values at a time.
    const Eigen::Vector4f fraction = camera.viewDepthFraction().cast<float>();
    Eigen::Map<Eigen::ArrayXf> window(depth.data(), static_cast<Eigen::Index>(pixels));
    window = (fraction[0] + fraction[1] * window) /
             ((fraction[2] + fraction[3] * window) * (1.0f - window.floor()));
  }

 private:
  /// A mesh in view this frame.
  struct Visible {
    const SceneMesh* mesh;
    const GpuMesh* gpu;
    double distance;  ///< of its bounding sphere's centre along the view axis [m]
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
    glAlphaFunc(GL_GREATER, kTextureAlphaCut);
    glEnableClientState(GL_VERTEX_ARRAY);
    initialised_ = true;
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

  /// The meshes whose bounding spheres reach into the view, nearest first: far surfaces hidden behind near
  /// ones then fail the depth test before llvmpipe shades them.
  void collectVisible(const Scene& scene, const Eigen::Matrix4d& clip, const Eigen::Matrix4d& view) {
    visible_.clear();
    const std::array<Eigen::Vector4d, 6> planes = frustumPlanes(clip);
    for (const SceneMesh& mesh : scene.meshes) {
      if (!mesh.mesh) continue;
      const GpuMesh& gpu = gpu_.mesh(mesh.mesh);
      const Eigen::Vector4d centre = (mesh.pose * gpu.centre).homogeneous();
      const bool outside = std::any_of(planes.begin(), planes.end(), [&](const Eigen::Vector4d& plane) {
        return plane.dot(centre) < -gpu.radius;
      });
      if (!outside) visible_.push_back({&mesh, &gpu, -view.row(2).dot(centre)});
    }
    std::stable_sort(visible_.begin(), visible_.end(),
                     [](const Visible& a, const Visible& b) { return a.distance < b.distance; });
  }

  /// Opaque meshes write depth. See-through ones (alpha < 1) blend over what is drawn before them, and only
  /// the nearest see-through surface of a pixel does, once: a depth-only pass finds it first.
  void drawMeshes(const Eigen::Matrix4d& view, bool translucent) {
    glEnable(GL_LIGHTING);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glEnableClientState(GL_NORMAL_ARRAY);
    if (translucent) {
      glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      drawMeshesOfKind(view, translucent);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glEnable(GL_BLEND);
      glDepthMask(GL_FALSE);
    }
    drawMeshesOfKind(view, translucent);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    glDisable(GL_CULL_FACE);
    setTexture(nullptr, translucent);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_LIGHTING);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
  }

  /// Draws the parts of the visible meshes that are see-through or not, as `translucent` says.
  void drawMeshesOfKind(const Eigen::Matrix4d& view, bool translucent) {
    for (const Visible& visible : visible_) {
      const SceneMesh& mesh = *visible.mesh;
      const std::vector<MeshPart>& parts = mesh.mesh->parts;
      bool bound = false;
      const auto draw = [&](int first_triangle, int triangles, const Look& look) {
        if ((look.rgba[3] < 1) != translucent) return;
        if (!bound) bindMesh(view, mesh, *visible.gpu);
        bound = true;
        setColour(look.rgba);
        setTexture(look.texture, translucent);
        glDrawElements(GL_TRIANGLES, 3 * triangles, GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(3 * sizeof(GLuint) * first_triangle));
      };
      if (parts.empty()) draw(0, static_cast<int>(mesh.mesh->triangles.size()), lookOf(mesh, nullptr));
      for (const MeshPart& part : parts) {
        draw(part.first_triangle, part.triangle_count, lookOf(mesh, &mesh.mesh->materials[part.material]));
      }
    }
  }

  static void bindMesh(const Eigen::Matrix4d& view, const SceneMesh& mesh, const GpuMesh& gpu) {
    const Eigen::Matrix4d model_view = view * mesh.pose.matrix();
    glLoadMatrixd(model_view.data());
    // The backs of a closed shape's triangles lie behind its fronts: skipping them halves its rasterising.
    if (mesh.mesh->closed) {
      glEnable(GL_CULL_FACE);
    } else {
      glDisable(GL_CULL_FACE);
    }
    glBindBuffer(GL_ARRAY_BUFFER, gpu.vertices);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.indices);
    glVertexPointer(3, GL_FLOAT, gpu.stride, nullptr);
    glNormalPointer(GL_FLOAT, gpu.stride, reinterpret_cast<const void*>(3 * sizeof(float)));
    if (gpu.has_uvs) {
      glEnableClientState(GL_TEXTURE_COORD_ARRAY);
      glTexCoordPointer(2, GL_FLOAT, gpu.stride, reinterpret_cast<const void*>(6 * sizeof(float)));
    } else {
      glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
  }

  /// Texels multiply the lit colour; the clearest are cut away. Opaque textured surfaces leave the picture's
  /// alpha as it is (a texel's alpha is not the picture's).
  void setTexture(const std::shared_ptr<const Texture>* texture, bool translucent) {
    if (!texture) {
      glDisable(GL_TEXTURE_2D);
      glDisable(GL_ALPHA_TEST);
      if (!translucent) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      return;
    }
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, gpu_.texture(*texture));
    glEnable(GL_ALPHA_TEST);
    if (!translucent) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
  }

  static void drawPoints(const Scene& scene, bool overlay) {
    for (const PointSet& set : scene.point_sets) {
      if (set.overlay != overlay) continue;
      setColour(set.rgba);
      glPointSize(static_cast<GLfloat>(set.size));
      drawVertices(GL_POINTS, set.points);
    }
  }

  OSMesaContext context_;
  std::vector<uint8_t> pixels_;  ///< RGBA, top row first
  bool initialised_ = false;
  GpuResources gpu_;
  std::vector<Visible> visible_;  ///< this frame's, nearest first
};

OffscreenRenderer::OffscreenRenderer() : context_(std::make_unique<Context>()) {}
OffscreenRenderer::~OffscreenRenderer() = default;
OffscreenRenderer::OffscreenRenderer(OffscreenRenderer&&) noexcept = default;
OffscreenRenderer& OffscreenRenderer::operator=(OffscreenRenderer&&) noexcept = default;

OffscreenRenderer::Context& OffscreenRenderer::drawn(const Scene& scene, int width, int height,
                                                     std::vector<float>* depth) {
  if (!context_) throw std::logic_error("OffscreenRenderer: this renderer was moved from");
  context_->draw(scene, width, height);
  if (depth) Context::readDepth(scene.camera, width, height, *depth);
  return *context_;
}

Image OffscreenRenderer::render(const Scene& scene, int width, int height, std::vector<float>* depth) {
  return Image{width, height, drawn(scene, width, height, depth).pixels()};
}

void OffscreenRenderer::renderRgb(const Scene& scene, int width, int height, std::vector<uint8_t>& rgb,
                                  std::vector<float>* depth) {
  const std::vector<uint8_t>& rgba = drawn(scene, width, height, depth).pixels();
  dropAlpha(rgba.data(), rgba.size() / 4, rgb);
}

}  // namespace bullet_sim
