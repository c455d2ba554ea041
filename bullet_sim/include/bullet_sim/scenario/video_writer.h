// An MP4 file of rendered frames, encoded by FFmpeg's libraries (libavcodec, libavformat, libswscale):
// H.264 when the library has an H.264 encoder, MPEG-4 part 2 otherwise.
#pragma once

#include <memory>
#include <string>

#include "bullet_sim/scene/image.h"

namespace bullet_sim {

class VideoWriter {
 public:
  /// Opens `path` for frames of width x height (even numbers) at `fps`, encoded on one thread. Throws
  /// std::runtime_error naming the path and FFmpeg's reason.
  VideoWriter(const std::string& path, int width, int height, int fps);
  /// Finishes the file when finish() was not called (errors are then dropped).
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Appends a frame of the writer's size; std::invalid_argument for another size.
  void add(const Image& image);
  /// Flushes the encoder and writes the file's index. Throws std::runtime_error when it cannot.
  void finish();
  int frames() const { return frames_; }

 private:
  struct Codec;
  std::unique_ptr<Codec> codec_;
  int frames_ = 0;
};

}  // namespace bullet_sim
