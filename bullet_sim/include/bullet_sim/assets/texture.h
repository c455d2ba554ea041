// Images that meshes are painted with: PNG (libpng) and JPEG (libjpeg), decoded once per file and bounded in
// size.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bullet_sim {

struct Texture {
  int width = 0;              ///< [px]
  int height = 0;             ///< [px]
  std::vector<uint8_t> rgba;  ///< 4 bytes per pixel, rows top first, each row left to right
  std::string source;         ///< the file it came from, or the mesh it was embedded in, for messages
};

/// The most pixels a texture may have once decoded (4096 x 4096, 64 MiB of RGBA), and the longest side. A
/// larger JPEG is decoded at 1/2, 1/4 or 1/8 of its size, as libjpeg can; a larger PNG is refused.
struct TextureLimits {
  int64_t max_pixels = 4096 * 4096;
  int max_side = 16384;  ///< [px], llvmpipe's largest texture
};

/// The largest image file loadTexture reads [bytes].
constexpr std::uintmax_t kMaxTextureFileBytes = 128u << 20;

/// Decodes a PNG or JPEG image (told apart by its contents, not its name) into RGBA. nullopt with `error`
/// naming `source` and the reason when the bytes are neither, are damaged, or exceed `limits`.
std::optional<Texture> decodeTexture(const uint8_t* data, size_t size, const std::string& source,
                                     std::string* error, const TextureLimits& limits = {});

/// Reads and decodes an image file: a regular file of at most kMaxTextureFileBytes.
std::optional<Texture> loadTexture(const std::string& path, std::string* error,
                                   const TextureLimits& limits = {});

/// Decodes each image file once: every mesh that names the same file shares one Texture. It also bounds what
/// all its textures take together, so that many large images cannot exhaust memory either.
class TextureCache {
 public:
  static constexpr int64_t kDefaultBudget = int64_t{1} << 30;  ///< [bytes] of decoded RGBA, 1 GiB

  explicit TextureCache(int64_t budget_bytes = kDefaultBudget) : budget_(budget_bytes) {}

  /// The texture in the file at `path`; nullptr with `error` set when it cannot be decoded or would exceed
  /// the budget (a file that failed is not read again).
  std::shared_ptr<const Texture> load(const std::string& path, std::string* error);
  /// An image held in memory (embedded in a mesh file), decoded and counted against the budget.
  std::shared_ptr<const Texture> decode(const uint8_t* data, size_t size, const std::string& source,
                                        std::string* error);
  /// A texture decoded elsewhere, counted against the budget; nullptr with `error` set when over it.
  std::shared_ptr<const Texture> adopt(Texture texture, std::string* error);

 private:
  struct Entry {
    std::shared_ptr<const Texture> texture;  ///< nullptr: it failed, for `error`
    std::string error;
  };
  std::map<std::string, Entry> textures_;  ///< by canonical path
  int64_t budget_;                         ///< [bytes] left
};

}  // namespace bullet_sim
