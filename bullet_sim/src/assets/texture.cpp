#include "bullet_sim/assets/texture.h"

#include <jpeglib.h>
#include <png.h>

#include <csetjmp>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace bullet_sim {

namespace fs = std::filesystem;

namespace {

/// Why an image of width x height does not fit `limits`, or "" when it does.
std::string tooLarge(int64_t width, int64_t height, const TextureLimits& limits) {
  if (width * height <= limits.max_pixels && width <= limits.max_side && height <= limits.max_side) return "";
  return "is " + std::to_string(width) + " x " + std::to_string(height) +
         " px, more than bullet_sim decodes (" + std::to_string(limits.max_pixels) + " pixels, " +
         std::to_string(limits.max_side) + " px a side); scale the image down";
}

std::optional<Texture> decodePng(const uint8_t* data, size_t size, std::string* error,
                                 const TextureLimits& limits) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, data, size)) {
    *error = std::string("damaged PNG: ") + image.message;
    return std::nullopt;
  }
  if (const std::string why = tooLarge(image.width, image.height, limits); !why.empty()) {
    png_image_free(&image);
    *error = why;
    return std::nullopt;
  }
  image.format = PNG_FORMAT_RGBA;  // any PNG: palette, grey, 16-bit, with or without alpha
  Texture texture;
  texture.width = static_cast<int>(image.width);
  texture.height = static_cast<int>(image.height);
  texture.rgba.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, texture.rgba.data(), 0, nullptr)) {
    *error = std::string("damaged PNG: ") + image.message;
    return std::nullopt;
  }
  return texture;
}

/// libjpeg reports a fatal error by calling error_exit, which must not return: it jumps back to the decoder.
struct JpegErrors {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void jpegFailed(j_common_ptr info) {
  auto* errors = reinterpret_cast<JpegErrors*>(info->err);
  errors->manager.format_message(info, errors->message);
  std::longjmp(errors->jump, 1);
}

/// Decodes into `texture`, halving the image (libjpeg's scaling) until it fits `limits`. False with
/// `errors.message` set when libjpeg fails, or with it empty when even 1/8 is too large. No C++ object of
/// this function lives across a libjpeg call, as the longjmp out of one skips destructors.
bool decodeJpegInto(jpeg_decompress_struct& info, JpegErrors& errors, const uint8_t* data, size_t size,
                    const TextureLimits& limits, Texture& texture) {
  if (setjmp(errors.jump)) return false;
  jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
  jpeg_read_header(&info, TRUE);
  info.scale_num = 1;
  info.scale_denom = 1;
  while (info.scale_denom < 8 &&
         !tooLarge((info.image_width + info.scale_denom - 1) / info.scale_denom,
                   (info.image_height + info.scale_denom - 1) / info.scale_denom, limits)
              .empty()) {
    info.scale_denom *= 2;
  }
  info.out_color_space = JCS_EXT_RGBA;  // libjpeg-turbo's; grey and YCbCr JPEGs alike
  jpeg_start_decompress(&info);
  if (!tooLarge(info.output_width, info.output_height, limits).empty()) return false;
  texture.width = static_cast<int>(info.output_width);
  texture.height = static_cast<int>(info.output_height);
  texture.rgba.resize(static_cast<size_t>(texture.width) * texture.height * 4);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = &texture.rgba[static_cast<size_t>(info.output_scanline) * texture.width * 4];
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  return true;
}

std::optional<Texture> decodeJpeg(const uint8_t* data, size_t size, std::string* error,
                                  const TextureLimits& limits) {
  jpeg_decompress_struct info{};
  JpegErrors errors{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = jpegFailed;
  errors.manager.output_message = [](j_common_ptr) {};  // warnings about recoverable damage stay quiet
  jpeg_create_decompress(&info);
  Texture texture;
  const bool decoded = decodeJpegInto(info, errors, data, size, limits, texture);
  const int64_t width = info.image_width, height = info.image_height;
  jpeg_destroy_decompress(&info);
  if (decoded) return texture;
  *error = errors.message[0] ? std::string("not a PNG or a readable JPEG (libjpeg: ") + errors.message + ")"
                             : tooLarge(width, height, limits);
  return std::nullopt;
}

}  // namespace

std::optional<Texture> decodeTexture(const uint8_t* data, size_t size, const std::string& source,
                                     std::string* error, const TextureLimits& limits) {
  std::string why;
  std::optional<Texture> texture = size >= 8 && png_sig_cmp(data, 0, 8) == 0
                                       ? decodePng(data, size, &why, limits)
                                       : decodeJpeg(data, size, &why, limits);
  if (!texture) {
    if (error) *error = "image [" + source + "]: " + why;
    return std::nullopt;
  }
  texture->source = source;
  return texture;
}

std::optional<Texture> loadTexture(const std::string& path, std::string* error, const TextureLimits& limits) {
  std::error_code ec;
  const auto fail = [&](const std::string& why) -> std::optional<Texture> {
    if (error) *error = "image [" + path + "]: " + why;
    return std::nullopt;
  };
  if (!fs::exists(path, ec)) return fail("no such file");
  if (!fs::is_regular_file(path, ec)) return fail("not a regular file");
  if (fs::file_size(path, ec) > kMaxTextureFileBytes) {
    return fail("larger than " + std::to_string(kMaxTextureFileBytes >> 20) + " MiB");
  }
  std::ifstream file(path, std::ios::binary);
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (!file && !file.eof()) return fail("cannot be read");
  return decodeTexture(bytes.data(), bytes.size(), path, error, limits);
}

std::shared_ptr<const Texture> TextureCache::load(const std::string& path, std::string* error) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(path, ec);
  const auto [entry, added] = textures_.try_emplace(ec ? path : canonical.string());
  if (added) {
    if (std::optional<Texture> texture = loadTexture(path, &entry->second.error)) {
      entry->second.texture = adopt(std::move(*texture), &entry->second.error);
    }
  }
  if (!entry->second.texture && error) *error = entry->second.error;
  return entry->second.texture;
}

std::shared_ptr<const Texture> TextureCache::decode(const uint8_t* data, size_t size,
                                                    const std::string& source, std::string* error) {
  std::optional<Texture> texture = decodeTexture(data, size, source, error);
  return texture ? adopt(std::move(*texture), error) : nullptr;
}

std::shared_ptr<const Texture> TextureCache::adopt(Texture texture, std::string* error) {
  const auto bytes = static_cast<int64_t>(texture.rgba.size());
  if (bytes > budget_) {
    if (error) {
      *error = "image [" + texture.source + "] is not drawn: the textures of one world or robot may take " +
               std::to_string(kDefaultBudget >> 20) + " MiB at most, and the others took that";
    }
    return nullptr;
  }
  budget_ -= bytes;
  return std::make_shared<const Texture>(std::move(texture));
}

}  // namespace bullet_sim
