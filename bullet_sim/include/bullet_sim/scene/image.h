// An RGBA8 picture: what a renderer draws.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bullet_sim {

struct Image {
  int width = 0;              ///< [px]
  int height = 0;             ///< [px]
  std::vector<uint8_t> rgba;  ///< 4 bytes per pixel, rows top first, each row left to right

  /// The RGBA of the pixel in `column` (from the left) and `row` (from the top).
  std::array<uint8_t, 4> at(int column, int row) const {
    const uint8_t* pixel = &rgba[(static_cast<size_t>(row) * width + column) * 4];
    return {pixel[0], pixel[1], pixel[2], pixel[3]};
  }
};

/// The RGB of `pixels` RGBA pixels into `rgb`, 3 bytes per pixel in the same order. `rgb` keeps its storage
/// when it is large enough.
void dropAlpha(const uint8_t* rgba, size_t pixels, std::vector<uint8_t>& rgb);

}  // namespace bullet_sim
