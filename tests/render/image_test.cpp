#include "cgamesh/render/image.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

namespace {

namespace render = cgamesh::render;

render::Image gradient(int w, int h, std::uint8_t blue) {
  render::Image im{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w * h * 4))};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = im.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(x * 7);
      p[1] = static_cast<std::uint8_t>(y * 5);
      p[2] = blue;
      p[3] = 255;
    }
  return im;
}

TEST(Image, PngRoundTripIsExact) {
  const render::Image im = gradient(37, 21, 90);
  const std::string png = render::encode_png(im);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const render::Image back =
      render::decode_image(std::span(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()), "round trip");
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 21);
  EXPECT_EQ(back.rgba, im.rgba);
}

TEST(Image, BadImagesAreErrors) {
  EXPECT_THROW(static_cast<void>(render::encode_png(render::Image{})), cgamesh::InvalidInputError);
  EXPECT_THROW(static_cast<void>(render::encode_png(render::Image{2, 2, std::vector<std::uint8_t>(15)})),
               cgamesh::InvalidInputError);
  const std::vector<std::uint8_t> junk{1, 2, 3, 4, 5, 6, 7, 8, 9};
  EXPECT_THROW(static_cast<void>(render::decode_image(junk, "junk")), cgamesh::FileError);
  EXPECT_THROW(static_cast<void>(render::decode_image({}, "empty")), cgamesh::FileError);
}

TEST(Image, ContactSheetTilesRowByRow) {
  const std::vector<render::Image> images{gradient(4, 3, 10), gradient(4, 3, 20), gradient(4, 3, 30)};
  const render::Image sheet = render::contact_sheet(images, 2, {1, 0, 0});
  ASSERT_EQ(sheet.width, 8);
  ASSERT_EQ(sheet.height, 6);
  EXPECT_EQ(sheet.pixel(0, 0)[2], 10);
  EXPECT_EQ(sheet.pixel(4, 0)[2], 20);
  EXPECT_EQ(sheet.pixel(1, 3)[2], 30);
  EXPECT_EQ(sheet.pixel(1, 3)[0], images[2].pixel(1, 0)[0]);
  // The empty cell is background.
  EXPECT_EQ(sheet.pixel(6, 4)[0], 255);
  EXPECT_EQ(sheet.pixel(6, 4)[1], 0);
  EXPECT_THROW(static_cast<void>(render::contact_sheet({}, 2, {1, 1, 1})), cgamesh::InvalidInputError);
  EXPECT_THROW(static_cast<void>(render::contact_sheet(images, 0, {1, 1, 1})), cgamesh::InvalidInputError);
}

}  // namespace
