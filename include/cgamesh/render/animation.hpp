#pragma once
// Moving pictures: a sequence of rendered frames encoded as one animated WebP (libwebp's
// WebPAnimEncoder), which browsers, GitHub's README view and image viewers play.

#include <filesystem>
#include <span>
#include <string>

#include "cgamesh/render/image.hpp"

namespace cgamesh::render {

struct AnimationOptions {
  double frame_seconds = 1.0 / 24.0;  ///< how long each frame shows (> 0, at most 60 s)
  bool lossless = false;              ///< lossless frames (larger); lossy at `quality` otherwise
  float quality = 85;                 ///< lossy quality in [0, 100]
  int loops = 0;                      ///< times it plays; 0: forever
};

/// Frame times over a time range: `frames` frames from `start` (shown first) towards `end`,
/// each `(end − start) / frames` seconds apart, so that a clip of length end − start loops
/// without a repeated frame.
struct FrameTimes {
  double start = 0, end = 0;
  int frames = 1;
  /// The largest number of frames.
  static constexpr int kMaxFrames = 10000;

  /// "START:END:N" (seconds, seconds, a count).
  /// @throws InvalidInputError naming `option` for anything else, a negative or non-finite
  ///         time, END ≤ START, or N outside [1, kMaxFrames].
  [[nodiscard]] static FrameTimes parse(const std::string& text, const std::string& option);
  [[nodiscard]] double time(int k) const noexcept { return start + (end - start) * k / frames; }
  [[nodiscard]] double frame_seconds() const noexcept { return (end - start) / frames; }
};

/// The frames as an animated WebP, each shown for options.frame_seconds.
/// @param[in] frames  images of one size, at most 16383 pixels a side (WebP's limit)
/// @throws InvalidInputError for no frames, frames of different sizes, a side over WebP's
///         limit or a bad option (naming it).
[[nodiscard]] std::string encode_webp_animation(std::span<const Image> frames, const AnimationOptions& options = {});

/// Writes encode_webp_animation() all or nothing (io/atomic_file.hpp).
/// @throws as encode_webp_animation(); WriteError when the file cannot be written.
void write_webp_animation(std::span<const Image> frames, const std::filesystem::path& path,
                          const AnimationOptions& options = {});

}  // namespace cgamesh::render
