#include "cgamesh/render/animation.hpp"

#include <cmath>
#include <memory>
#include <string>

#include <webp/encode.h>
#include <webp/mux.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/io/text_values.hpp"

namespace cgamesh::render {
namespace {

/// WebP's largest side.
constexpr int kMaxWebpSide = WEBP_MAX_DIMENSION;

void validate(std::span<const Image> frames, const AnimationOptions& options) {
  if (frames.empty()) throw InvalidInputError("animation: no frames");
  for (const Image& f : frames) {
    render::validate(f);
    if (f.width != frames.front().width || f.height != frames.front().height)
      throw InvalidInputError("animation: frames of different sizes (" + std::to_string(f.width) + "x" +
                              std::to_string(f.height) + " after " + std::to_string(frames.front().width) + "x" +
                              std::to_string(frames.front().height) + ")");
  }
  if (frames.front().width > kMaxWebpSide || frames.front().height > kMaxWebpSide)
    throw InvalidInputError("animation: WebP frames are at most " + std::to_string(kMaxWebpSide) + " pixels a side");
  if (!(options.frame_seconds > 0 && options.frame_seconds <= 60))
    throw InvalidInputError("animation: frame_seconds must be in (0, 60]");
  if (!(options.quality >= 0 && options.quality <= 100))
    throw InvalidInputError("animation: quality must be in [0, 100]");
  if (options.loops < 0 || options.loops > 65535) throw InvalidInputError("animation: loops must be in [0, 65535]");
}

}  // namespace

FrameTimes FrameTimes::parse(const std::string& text, const std::string& option) {
  const auto bad = [&](const std::string& why) {
    return InvalidInputError(option + " '" + text.substr(0, 64) + "': " + why);
  };
  const std::size_t a = text.find(':'), b = a == std::string::npos ? a : text.find(':', a + 1);
  if (b == std::string::npos || text.find(':', b + 1) != std::string::npos)
    throw bad("expected START:END:N (seconds, seconds, a frame count)");
  const auto real = [&](const std::string& part, const char* what) {
    double v = -1;
    try {
      v = io::parse_numbers(part, 1, what)[0];
    } catch (const InvalidInputError&) {  // said below, naming the part of `option`
    }
    if (!(v >= 0)) throw bad(std::string(what) + " must be a finite number of seconds >= 0");
    return v;
  };
  FrameTimes t;
  t.start = real(text.substr(0, a), "START");
  t.end = real(text.substr(a + 1, b - a - 1), "END");
  if (!(t.end > t.start)) throw bad("END must be after START");
  const std::string n = text.substr(b + 1);
  if (n.empty() || n.size() > 6 || n.find_first_not_of("0123456789") != std::string::npos)
    throw bad("N must be a whole number of frames");
  t.frames = std::stoi(n);
  if (t.frames < 1 || t.frames > kMaxFrames) throw bad("N must be 1 to " + std::to_string(kMaxFrames));
  return t;
}

std::string encode_webp_animation(std::span<const Image> frames, const AnimationOptions& options) {
  validate(frames, options);
  const int width = frames.front().width, height = frames.front().height;
  WebPAnimEncoderOptions encoder_options;
  if (WebPAnimEncoderOptionsInit(&encoder_options) == 0) throw Error("animation: libwebp version mismatch");
  encoder_options.anim_params.loop_count = options.loops;
  const std::unique_ptr<WebPAnimEncoder, void (*)(WebPAnimEncoder*)> encoder(
      WebPAnimEncoderNew(width, height, &encoder_options), WebPAnimEncoderDelete);
  if (!encoder) throw Error("animation: libwebp could not make an encoder (out of memory?)");
  WebPConfig config;
  if (WebPConfigInit(&config) == 0) throw Error("animation: libwebp version mismatch");
  config.lossless = options.lossless ? 1 : 0;
  config.quality = options.quality;
  // Timestamps in whole milliseconds, rounded from the exact time of each frame so that long
  // sequences do not drift.
  const auto stamp = [&](std::size_t k) {
    return static_cast<int>(std::lround(static_cast<double>(k) * options.frame_seconds * 1000.0));
  };
  for (std::size_t k = 0; k < frames.size(); ++k) {
    WebPPicture picture;
    if (WebPPictureInit(&picture) == 0) throw Error("animation: libwebp version mismatch");
    picture.use_argb = 1;
    picture.width = width;
    picture.height = height;
    const std::unique_ptr<WebPPicture, void (*)(WebPPicture*)> owned(&picture, WebPPictureFree);
    if (WebPPictureImportRGBA(&picture, frames[k].rgba.data(), width * 4) == 0)
      throw Error("animation: libwebp could not take frame " + std::to_string(k) + " (out of memory?)");
    if (WebPAnimEncoderAdd(encoder.get(), &picture, stamp(k), &config) == 0)
      throw Error("animation: frame " + std::to_string(k) + ": " + WebPAnimEncoderGetError(encoder.get()));
  }
  if (WebPAnimEncoderAdd(encoder.get(), nullptr, stamp(frames.size()), nullptr) == 0)
    throw Error(std::string("animation: ") + WebPAnimEncoderGetError(encoder.get()));
  WebPData data;
  WebPDataInit(&data);
  if (WebPAnimEncoderAssemble(encoder.get(), &data) == 0)
    throw Error(std::string("animation: ") + WebPAnimEncoderGetError(encoder.get()));
  std::string out(reinterpret_cast<const char*>(data.bytes), data.size);
  WebPDataClear(&data);
  return out;
}

void write_webp_animation(std::span<const Image> frames, const std::filesystem::path& path,
                          const AnimationOptions& options) {
  io::write_file_atomically(path, encode_webp_animation(frames, options));
}

}  // namespace cgamesh::render
