// What a camera plugin asks of a renderer: "draw the world from this pose at this size". The plugins layer
// only declares it; the scene layer implements it over the renderer, and whoever builds a simulation gives it
// one (SimulationOptions::images). A simulation without one never loads a renderer.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace bullet_sim {

struct ImageRequest {
  /// The camera in the world. It looks along its x axis with z up, as Gazebo's camera sensors do.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  int width = 320;  ///< [px]
  int height = 240;
  double horizontal_fov = 1.047;  ///< [rad]; pixels are square, so the vertical one follows
  double near_clip = 0.1;         ///< [m] along the view axis
  double far_clip = 100;
  bool depth = false;  ///< whether the depth map is wanted too
};

/// A rendered frame. Its buffers keep their storage from frame to frame, so that a camera that renders into
/// the same one every time allocates nothing.
struct RenderedImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;  ///< 3 bytes per pixel, rows top first
  /// Per pixel, the distance along the view axis [m] to what it shows; +inf where nothing lies within the
  /// clip range. Empty unless the request asked for depth.
  std::vector<float> depth;
};

class ImageSource {
 public:
  virtual ~ImageSource() = default;
  /// The world as it is now, seen from `request`, into `image` (its buffers are reused). Throws
  /// std::runtime_error when it cannot render.
  virtual void render(const ImageRequest& request, RenderedImage& image) = 0;
};

}  // namespace bullet_sim
