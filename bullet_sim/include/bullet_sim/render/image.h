// An Image's PNG file.
#pragma once

#include <string>

#include "bullet_sim/scene/image.h"

namespace bullet_sim {

/// Writes `image` as an 8-bit RGBA PNG, compressed for speed (zlib level 1, no filter) rather than size.
/// On failure returns false and sets `error` to what went wrong, naming the path.
bool writePng(const std::string& path, const Image& image, std::string* error);

}  // namespace bullet_sim
