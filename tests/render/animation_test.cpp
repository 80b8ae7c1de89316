#include "cgamesh/render/animation.hpp"

#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <webp/demux.h>

#include "cgamesh/errors.hpp"

namespace cgamesh::render {
namespace {

Image gradient(int width, int height, int shift) {
  Image im{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width * height * 4))};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = im.pixel(x, y);
      p[0] = static_cast<std::uint8_t>((x * 7 + shift) % 256);
      p[1] = static_cast<std::uint8_t>((y * 5) % 256);
      p[2] = static_cast<std::uint8_t>(shift * 40);
      p[3] = 255;
    }
  return im;
}

/// The frames and their end times (ms) as libwebp's own decoder reads them.
struct Decoded {
  std::vector<Image> frames;
  std::vector<int> end_ms;
  int loops = -1;
};

Decoded decode(const std::string& bytes) {
  WebPData data{reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()};
  WebPAnimDecoderOptions options;
  EXPECT_TRUE(WebPAnimDecoderOptionsInit(&options));
  options.color_mode = MODE_RGBA;
  WebPAnimDecoder* decoder = WebPAnimDecoderNew(&data, &options);
  Decoded out;
  if (decoder == nullptr) {
    ADD_FAILURE() << "libwebp does not read the animation";
    return out;
  }
  WebPAnimInfo info;
  EXPECT_TRUE(WebPAnimDecoderGetInfo(decoder, &info));
  out.loops = static_cast<int>(info.loop_count);
  while (WebPAnimDecoderHasMoreFrames(decoder) != 0) {
    std::uint8_t* pixels = nullptr;
    int timestamp = 0;
    if (WebPAnimDecoderGetNext(decoder, &pixels, &timestamp) == 0) break;
    const auto w = static_cast<int>(info.canvas_width), h = static_cast<int>(info.canvas_height);
    out.frames.push_back({w, h, std::vector<std::uint8_t>(pixels, pixels + static_cast<std::size_t>(w * h * 4))});
    out.end_ms.push_back(timestamp);
  }
  WebPAnimDecoderDelete(decoder);
  return out;
}

TEST(Animation, LosslessFramesReadBackExactlyWithTheirTimes) {
  const std::vector<Image> frames{gradient(40, 30, 0), gradient(40, 30, 1), gradient(40, 30, 2)};
  AnimationOptions options;
  options.lossless = true;
  options.frame_seconds = 0.1;
  const Decoded d = decode(encode_webp_animation(frames, options));
  ASSERT_EQ(d.frames.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(d.frames[k].rgba, frames[k].rgba) << "frame " << k;
  EXPECT_EQ(d.end_ms, (std::vector<int>{100, 200, 300}));
  EXPECT_EQ(d.loops, 0) << "plays forever";
}

TEST(Animation, LossyFramesStayClose) {
  const std::vector<Image> frames{gradient(64, 48, 0), gradient(64, 48, 3)};
  const Decoded d = decode(encode_webp_animation(frames));
  ASSERT_EQ(d.frames.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    double sum = 0;
    for (std::size_t i = 0; i < frames[k].rgba.size(); ++i)
      sum += std::abs(static_cast<int>(d.frames[k].rgba[i]) - static_cast<int>(frames[k].rgba[i]));
    EXPECT_LT(sum / static_cast<double>(frames[k].rgba.size()), 8.0) << "mean error per channel, frame " << k;
  }
}

TEST(Animation, BadFramesAndOptionsAreRefused) {
  EXPECT_THROW((void)encode_webp_animation({}), InvalidInputError);
  const std::vector<Image> mixed{gradient(4, 4, 0), gradient(5, 4, 0)};
  EXPECT_THROW((void)encode_webp_animation(mixed), InvalidInputError);
  const std::vector<Image> one{gradient(4, 4, 0)};
  AnimationOptions bad;
  bad.frame_seconds = 0;
  EXPECT_THROW((void)encode_webp_animation(one, bad), InvalidInputError);
  bad = {};
  bad.quality = 101;
  EXPECT_THROW((void)encode_webp_animation(one, bad), InvalidInputError);
  Image broken = gradient(4, 4, 0);
  broken.rgba.pop_back();
  EXPECT_THROW((void)encode_webp_animation(std::vector<Image>{broken}), InvalidInputError);
}

TEST(FrameTimes, ParsedAndSpacedToLoop) {
  const FrameTimes t = FrameTimes::parse("0:2:60", "--time");
  EXPECT_EQ(t.frames, 60);
  EXPECT_DOUBLE_EQ(t.time(0), 0.0);
  EXPECT_DOUBLE_EQ(t.time(30), 1.0);
  EXPECT_DOUBLE_EQ(t.frame_seconds(), 2.0 / 60);
  EXPECT_LT(t.time(59), 2.0) << "the end is the next loop's first frame";
  for (const char* bad : {"", "1", "0:2", "0:2:", "2:1:10", "1:1:5", "0:2:0", "0:2:10001", "0:nan:5", "-1:2:5",
                          "0:2:5:1", "0:2:5.5", "0:2:x", "a:2:5"}) {
    try {
      (void)FrameTimes::parse(bad, "--time");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InvalidInputError& e) {
      EXPECT_NE(std::string(e.what()).find("--time"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace cgamesh::render
