#include "bullet_sim/render/image.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

namespace bullet_sim {

namespace {

/// Where libpng's error handler leaves its message. Plain data: libpng longjmps past it.
struct PngFailure {
  char message[256] = "";
};

void onPngError(png_structp png, png_const_charp message) {
  auto* failure = static_cast<PngFailure*>(png_get_error_ptr(png));
  std::snprintf(failure->message, sizeof failure->message, "%s", message);
  png_longjmp(png, 1);
}

void ignorePngWarning(png_structp, png_const_charp) {}  // writing a plain RGBA image raises none that matter

/// Encodes `image` into `file`. libpng reports errors by longjmp to the setjmp below, skipping destructors,
/// so no object with a destructor lives in this frame.
bool encodePng(FILE* file, const Image& image, png_bytep* rows, PngFailure* failure) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, failure, onPngError, ignorePngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    std::snprintf(failure->message, sizeof failure->message, "libpng is out of memory");
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // Speed over size: a 640 x 480 render compresses in a few milliseconds instead of tens.
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

bool writePng(const std::string& path, const Image& image, std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = "cannot write PNG [" + path + "]: " + why;
    return false;
  };
  if (image.width < 1 || image.height < 1 ||
      image.rgba.size() != static_cast<size_t>(image.width) * image.height * 4) {
    return fail("the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " pixels but holds " + std::to_string(image.rgba.size()) + " bytes instead of 4 per pixel");
  }
  FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) {
    return fail(std::string(std::strerror(errno)) + "; check that its directory exists and is writable");
  }
  std::vector<png_bytep> rows(image.height);
  for (int row = 0; row < image.height; ++row) {
    // libpng only reads the rows, but its API takes them as non-const.
    rows[row] = const_cast<png_bytep>(&image.rgba[static_cast<size_t>(row) * image.width * 4]);
  }
  PngFailure failure;
  const bool encoded = encodePng(file, image, rows.data(), &failure);
  const bool closed = std::fclose(file) == 0;  // flushes: a full disk shows here
  if (!encoded || !closed) {
    const std::string why = encoded ? std::strerror(errno) : failure.message;
    std::remove(path.c_str());
    return fail(why);
  }
  return true;
}

}  // namespace bullet_sim
