#include "cgamesh/render/image.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

#include "support/jpeg.hpp"

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

/// Smooth ramps (a lossy encoding keeps them within a few levels): red along x, green along y.
render::Image ramps(int w, int h) {
  render::Image im = gradient(w, h, 90);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      im.pixel(x, y)[0] = static_cast<std::uint8_t>(x * 255 / (w - 1));
      im.pixel(x, y)[1] = static_cast<std::uint8_t>(y * 255 / (h - 1));
    }
  return im;
}

/// The largest difference of a channel between two images of the same size.
int largest_difference(const render::Image& a, const render::Image& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  if (a.rgba.size() != b.rgba.size()) return 256;
  int d = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) d = std::max(d, std::abs(int{a.rgba[i]} - int{b.rgba[i]}));
  return d;
}

render::Image decode(const std::vector<std::uint8_t>& bytes, std::vector<std::string>* warnings = nullptr) {
  return render::decode_image(bytes, "texture 'dwarf.jpg'", warnings);
}

/// The message of the FileError that decoding `bytes` throws, or "" when none is thrown.
std::string decode_error(const std::vector<std::uint8_t>& bytes) {
  try {
    static_cast<void>(decode(bytes));
  } catch (const cgamesh::FileError& e) {
    return e.what();
  }
  return "";
}

TEST(Image, JpegsOfEveryKindBrowsersShowDecode) {
  using cgamesh_test::JpegColors;
  const render::Image im = ramps(61, 37);
  render::Image grey = im;
  for (std::size_t i = 0; i < grey.rgba.size(); i += 4) grey.rgba[i + 1] = grey.rgba[i + 2] = grey.rgba[i];
  for (const bool progressive : {false, true}) {
    SCOPED_TRACE(progressive ? "progressive" : "baseline");
    std::vector<std::string> warnings;
    EXPECT_LE(largest_difference(decode(cgamesh_test::encode_jpeg(im, progressive), &warnings), im), 6);
    EXPECT_LE(largest_difference(decode(cgamesh_test::encode_jpeg(im, progressive, JpegColors::grey), &warnings), grey),
              2);
    EXPECT_LE(largest_difference(decode(cgamesh_test::encode_jpeg(im, progressive, JpegColors::cmyk), &warnings), im),
              2);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }
}

TEST(Image, JpegWithStrayBytesBeforeAMarkerDecodesAsLibjpegDoesWithAWarning) {
  const render::Image im = ramps(61, 37);
  for (const bool progressive : {false, true}) {
    SCOPED_TRACE(progressive ? "progressive" : "baseline");
    const std::vector<std::uint8_t> clean = cgamesh_test::encode_jpeg(im, progressive);
    const std::vector<std::uint8_t> damaged = cgamesh_test::with_stray_bytes_before_scans(clean, 3);
    ASSERT_GT(damaged.size(), clean.size());
    std::vector<std::string> warnings;
    // The same coded data: the same pixels.
    EXPECT_EQ(decode(damaged, &warnings).rgba, decode(clean).rgba);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].rfind("texture 'dwarf.jpg': Corrupt JPEG data: 3 extraneous bytes before marker 0xda", 0), 0u)
        << warnings[0];
    // A progressive file has a scan per band of frequencies: one warning for all of them.
    EXPECT_EQ(warnings[0].find("more libjpeg warnings") != std::string::npos, progressive) << warnings[0];
    EXPECT_EQ(decode(damaged).rgba, decode(clean).rgba);  // warnings are optional
  }
}

TEST(Image, TruncatedScansDecodeAsLibjpegDoesWithAWarning) {
  const render::Image im = ramps(61, 37);
  const std::vector<std::uint8_t> jpeg = cgamesh_test::encode_jpeg(im, false);
  const std::vector<std::size_t> markers = cgamesh_test::jpeg_markers(jpeg);
  const std::size_t scan =
      *std::find_if(markers.begin(), markers.end(), [&](std::size_t m) { return jpeg[m + 1] == 0xDA; });
  // Cut in the middle of the coded data: the top rows decode, libjpeg fills the rest.
  const std::vector<std::uint8_t> cut(jpeg.begin(),
                                      jpeg.begin() + static_cast<std::ptrdiff_t>((scan + jpeg.size()) / 2));
  std::vector<std::string> warnings;
  const render::Image decoded = decode(cut, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("Premature end of JPEG file"), std::string::npos) << warnings[0];
  EXPECT_LE(std::abs(int{decoded.pixel(30, 2)[0]} - int{im.pixel(30, 2)[0]}), 8);
}

TEST(Image, JpegsLibjpegCannotDecodeAreErrorsNamingTheImage) {
  const std::vector<std::uint8_t> jpeg = cgamesh_test::encode_jpeg(ramps(61, 37), true);
  // Cut in the header, before any scan.
  const std::string header = decode_error(std::vector<std::uint8_t>(jpeg.begin(), jpeg.begin() + 40));
  EXPECT_EQ(header.rfind("texture 'dwarf.jpg': cannot decode the JPEG (", 0), 0u) << header;
  // A JPEG signature and then garbage.
  std::vector<std::uint8_t> garbage{0xFF, 0xD8, 0xFF};
  for (int i = 0; i < 200; ++i) garbage.push_back(static_cast<std::uint8_t>(i * 37 + 11));
  const std::string junk = decode_error(garbage);
  EXPECT_EQ(junk.rfind("texture 'dwarf.jpg': cannot decode the JPEG (", 0), 0u) << junk;
}

TEST(Image, AbsurdDeclaredSizesAreRefusedBeforeDecoding) {
  // A JPEG whose frame header says 20000 x 30000 (2.4 GB of pixels) in a few hundred bytes.
  std::vector<std::uint8_t> jpeg = cgamesh_test::encode_jpeg(ramps(61, 37), true);
  for (const std::size_t m : cgamesh_test::jpeg_markers(jpeg))
    if (jpeg[m + 1] == 0xC2) {
      jpeg[m + 5] = 30000 >> 8;
      jpeg[m + 6] = 30000 & 0xFF;
      jpeg[m + 7] = 20000 >> 8;
      jpeg[m + 8] = 20000 & 0xFF;
    }
  EXPECT_NE(decode_error(jpeg).find("the image is 20000x30000 pixels; at most 16384 a side"), std::string::npos)
      << decode_error(jpeg);
  // The same for the formats stb_image decodes: a PNG's header says 20000 x 1.
  std::string png = render::encode_png(gradient(4, 4, 0));
  png[18] = static_cast<char>(20000 >> 8);
  png[19] = static_cast<char>(20000 & 0xFF);
  EXPECT_NE(decode_error(std::vector<std::uint8_t>(png.begin(), png.end())).find("20000x4"), std::string::npos);
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
