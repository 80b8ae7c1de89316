#pragma once
// JPEGs made in the tests with libjpeg: baseline or progressive encodings of an image, and the
// damage that browsers and libjpeg tolerate (stray bytes before a marker).

#include <cstddef>
#include <cstdint>
#include <cstdio>  // jpeglib.h uses FILE without including it
#include <cstdlib>
#include <jpeglib.h>
#include <vector>

#include "cgamesh/render/image.hpp"

namespace cgamesh_test {

/// How encode_jpeg() stores the colours.
enum class JpegColors {
  rgb,   ///< YCbCr, as cameras and most tools write
  grey,  ///< one channel: the image's red
  cmyk,  ///< Adobe (inverted) CMYK with no black, as Photoshop writes: C = R, M = G, Y = B, K = 255
};

/// The JPEG encoding of `image` (alpha dropped). Encoding a valid image cannot fail, so
/// libjpeg's default error handler (which exits) is kept.
inline std::vector<std::uint8_t> encode_jpeg(const cgamesh::render::Image& image, bool progressive,
                                             JpegColors colors = JpegColors::rgb, int quality = 95) {
  jpeg_compress_struct cinfo{};
  jpeg_error_mgr err{};
  cinfo.err = jpeg_std_error(&err);
  jpeg_create_compress(&cinfo);
  unsigned char* out = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &out, &size);
  const int channels = colors == JpegColors::grey ? 1 : colors == JpegColors::cmyk ? 4 : 3;
  cinfo.image_width = static_cast<JDIMENSION>(image.width);
  cinfo.image_height = static_cast<JDIMENSION>(image.height);
  cinfo.input_components = channels;
  cinfo.in_color_space = colors == JpegColors::grey ? JCS_GRAYSCALE : colors == JpegColors::cmyk ? JCS_CMYK : JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  if (progressive) jpeg_simple_progression(&cinfo);
  jpeg_start_compress(&cinfo, TRUE);
  std::vector<std::uint8_t> row(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(channels));
  while (cinfo.next_scanline < cinfo.image_height) {
    const std::uint8_t* p = image.pixel(0, static_cast<int>(cinfo.next_scanline));
    for (std::size_t x = 0; x < static_cast<std::size_t>(image.width); ++x)
      for (std::size_t c = 0; c < static_cast<std::size_t>(channels); ++c)
        row[x * static_cast<std::size_t>(channels) + c] = c < 3 ? p[x * 4 + c] : 255;
    JSAMPROW rows[1] = {row.data()};
    jpeg_write_scanlines(&cinfo, rows, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  std::vector<std::uint8_t> bytes(out, out + size);
  std::free(out);
  return bytes;
}

/// Offsets of the markers of `jpeg` after SOI, in order, up to EOI. Walks the segments: a table
/// may hold the bytes of a marker; coded data never does, but it has no length.
inline std::vector<std::size_t> jpeg_markers(const std::vector<std::uint8_t>& jpeg) {
  std::vector<std::size_t> markers;
  std::size_t i = 2;
  while (i + 4 <= jpeg.size() && jpeg[i] == 0xFF) {
    markers.push_back(i);
    if (jpeg[i + 1] == 0xD9) break;
    i += 2 + (static_cast<std::size_t>(jpeg[i + 2]) << 8 | jpeg[i + 3]);
    // A scan's coded data runs to the next marker that is neither a stuffed FF 00 nor a restart.
    if (jpeg[markers.back() + 1] == 0xDA)
      while (i + 1 < jpeg.size() &&
             !(jpeg[i] == 0xFF && jpeg[i + 1] != 0 && (jpeg[i + 1] < 0xD0 || jpeg[i + 1] > 0xD7)))
        ++i;
  }
  return markers;
}

/// `jpeg` with `count` zero bytes before each start-of-scan marker (FF DA): what libjpeg reports
/// as "extraneous bytes before marker 0xda" and decodes anyway.
inline std::vector<std::uint8_t> with_stray_bytes_before_scans(const std::vector<std::uint8_t>& jpeg,
                                                               std::size_t count) {
  std::vector<std::uint8_t> out;
  std::size_t copied = 0;
  for (const std::size_t m : jpeg_markers(jpeg)) {
    if (jpeg[m + 1] != 0xDA) continue;
    out.insert(out.end(), jpeg.begin() + static_cast<std::ptrdiff_t>(copied),
               jpeg.begin() + static_cast<std::ptrdiff_t>(m));
    out.insert(out.end(), count, 0);
    copied = m;
  }
  out.insert(out.end(), jpeg.begin() + static_cast<std::ptrdiff_t>(copied), jpeg.end());
  return out;
}

}  // namespace cgamesh_test
