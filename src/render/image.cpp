#include "cgamesh/render/image.hpp"

#include <algorithm>
#include <csetjmp>
#include <cstdio>  // jpeglib.h uses FILE without including it
#include <cstring>
#include <jpeglib.h>
#include <memory>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <climits>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"

namespace cgamesh::render {
namespace {

std::uint8_t to_byte(float c) { return static_cast<std::uint8_t>(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

/// Refuses an image whose header declares a side over kMaxImageSide, before its pixels are
/// allocated: a few bytes can declare gigabytes.
void check_declared_size(long width, long height, const std::string& what) {
  if (width > kMaxImageSide || height > kMaxImageSide)
    throw FileError(what + ": the image is " + std::to_string(width) + "x" + std::to_string(height) +
                    " pixels; at most " + std::to_string(kMaxImageSide) + " a side are decoded");
}

// libjpeg is C and reports errors through a callback that must not return: it longjmps back to
// the setjmp of the function below that called libjpeg (a C++ exception must not unwind C
// frames). Those functions keep nothing with a destructor in their frame; the callbacks write
// only these C buffers.
struct JpegErrors {
  jpeg_error_mgr mgr{};  // first member: libjpeg hands back &mgr
  std::jmp_buf jump{};
  char error[JMSG_LENGTH_MAX] = "";
  char first_warning[JMSG_LENGTH_MAX] = "";
};

JpegErrors& errors_of(j_common_ptr cinfo) { return *reinterpret_cast<JpegErrors*>(cinfo->err); }

[[noreturn]] void jpeg_error_exit(j_common_ptr cinfo) {
  JpegErrors& e = errors_of(cinfo);
  e.mgr.format_message(cinfo, e.error);
  std::longjmp(e.jump, 1);
}

// Level -1 is a warning (corrupt data libjpeg repaired); the others are trace messages.
void jpeg_emit_message(j_common_ptr cinfo, int level) {
  if (level >= 0) return;
  JpegErrors& e = errors_of(cinfo);
  if (e.mgr.num_warnings++ == 0) e.mgr.format_message(cinfo, e.first_warning);
}

/// Creates `cinfo` and reads the JPEG header; false (the message in errors.error) when libjpeg fails.
bool read_jpeg_header(jpeg_decompress_struct& cinfo, JpegErrors& errors, const std::uint8_t* data, std::size_t size) {
  if (setjmp(errors.jump) != 0) return false;
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  return true;
}

/// Decodes the pixels into `pixels` (output_width × output_height × 4 bytes, top row first);
/// false (the message in errors.error) when libjpeg fails.
bool read_jpeg_pixels(jpeg_decompress_struct& cinfo, JpegErrors& errors, std::uint8_t* pixels) {
  if (setjmp(errors.jump) != 0) return false;
  jpeg_start_decompress(&cinfo);
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = pixels + static_cast<std::size_t>(cinfo.output_scanline) * cinfo.output_width * 4;
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  return true;
}

Image decode_jpeg(std::span<const std::uint8_t> bytes, const std::string& what, std::vector<std::string>* warnings) {
  jpeg_decompress_struct cinfo{};  // zeroed: destroying it is a no-op until it is created
  JpegErrors errors;
  cinfo.err = jpeg_std_error(&errors.mgr);
  errors.mgr.error_exit = jpeg_error_exit;
  errors.mgr.emit_message = jpeg_emit_message;
  const std::unique_ptr<jpeg_decompress_struct, void (*)(j_decompress_ptr)> destroy(&cinfo, jpeg_destroy_decompress);
  const auto failed = [&] { return FileError(what + ": cannot decode the JPEG (" + errors.error + ")"); };
  if (!read_jpeg_header(cinfo, errors, bytes.data(), bytes.size())) throw failed();
  check_declared_size(cinfo.image_width, cinfo.image_height, what);
  // libjpeg gives RGBA from greyscale, YCbCr and RGB; Adobe CMYK (and YCCK, which it turns into
  // CMYK) is converted below.
  const bool cmyk = cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK;
  cinfo.out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
  Image out{static_cast<int>(cinfo.image_width), static_cast<int>(cinfo.image_height), {}};
  out.rgba.resize(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) * 4);
  if (!read_jpeg_pixels(cinfo, errors, out.rgba.data())) throw failed();
  if (cmyk) {
    // Adobe stores CMYK inverted (as browsers assume): R = C·K / 255 of the stored values.
    for (std::size_t i = 0; i < out.rgba.size(); i += 4) {
      const unsigned k = out.rgba[i + 3];
      for (std::size_t c = 0; c < 3; ++c)
        out.rgba[i + c] = static_cast<std::uint8_t>((out.rgba[i + c] * k + 127) / 255);
      out.rgba[i + 3] = 255;
    }
  }
  if (warnings && errors.mgr.num_warnings > 0)
    warnings->push_back(what + ": " + errors.first_warning +
                        (errors.mgr.num_warnings > 1
                             ? " (and " + std::to_string(errors.mgr.num_warnings - 1) + " more libjpeg warning" +
                                   (errors.mgr.num_warnings > 2 ? "s)" : ")")
                             : std::string()) +
                        "; decoded anyway");
  return out;
}

}  // namespace

void validate(const Image& image) {
  if (image.width <= 0 || image.height <= 0)
    throw InvalidInputError("image: empty (" + std::to_string(image.width) + "x" + std::to_string(image.height) + ")");
  if (image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
    throw InvalidInputError("image: " + std::to_string(image.rgba.size()) + " bytes for " +
                            std::to_string(image.width) + "x" + std::to_string(image.height) + " RGBA pixels");
}

std::string encode_png(const Image& image) {
  validate(image);
  std::string out;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (stbi_write_png_to_func(append, &out, image.width, image.height, 4, image.rgba.data(), image.width * 4) == 0)
    throw InvalidInputError("image: PNG encoding failed");
  return out;
}

void write_png(const Image& image, const std::filesystem::path& path) {
  io::write_file_atomically(path, encode_png(image));
}

Image decode_image(std::span<const std::uint8_t> bytes, const std::string& what, std::vector<std::string>* warnings) {
  if (bytes.empty() || bytes.size() > static_cast<std::size_t>(INT_MAX)) throw FileError(what + ": no image data");
  // Every JPEG starts with the SOI marker; libjpeg decodes what stb_image refuses (progressive
  // files with stray bytes before a marker) and says what it repaired.
  if (bytes.size() >= 2 && bytes[0] == 0xFF && bytes[1] == 0xD8) return decode_jpeg(bytes, what, warnings);
  int w = 0, h = 0, channels = 0;
  if (stbi_info_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &channels) != 0)
    check_declared_size(w, h, what);
  const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &channels, 4), stbi_image_free);
  if (!pixels) throw FileError(what + ": cannot decode the image (" + stbi_failure_reason() + ")");
  Image out{w, h, {}};
  out.rgba.assign(pixels.get(), pixels.get() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  return out;
}

std::string blank_warning(std::span<const Image> images, const std::string& view) {
  const auto uniform = [](const Image& image) {
    for (std::size_t i = 4; i + 3 < image.rgba.size(); i += 4)
      if (!std::equal(image.rgba.begin() + static_cast<std::ptrdiff_t>(i),
                      image.rgba.begin() + static_cast<std::ptrdiff_t>(i + 4), image.rgba.begin()))
        return false;
    return true;
  };
  if (images.empty() || !std::all_of(images.begin(), images.end(), uniform)) return "";
  return view + " shows nothing of the model: the picture is the background alone (single-sided faces seen "
                "from behind are not drawn, as in three.js; try the opposite view)";
}

Image contact_sheet(std::span<const Image> images, int columns, const Eigen::Vector3f& background) {
  if (images.empty()) throw InvalidInputError("contact sheet: no images");
  if (columns < 1) throw InvalidInputError("contact sheet: columns must be >= 1");
  int cw = 0, ch = 0;
  for (const Image& im : images) {
    validate(im);
    cw = std::max(cw, im.width);
    ch = std::max(ch, im.height);
  }
  const int cols = std::min<int>(columns, static_cast<int>(images.size()));
  const int rows = (static_cast<int>(images.size()) + cols - 1) / cols;
  Image out{cw * cols, ch * rows, {}};
  out.rgba.resize(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) * 4);
  const std::uint8_t bg[4] = {to_byte(background.x()), to_byte(background.y()), to_byte(background.z()), 255};
  for (std::size_t i = 0; i < out.rgba.size(); i += 4) std::memcpy(&out.rgba[i], bg, 4);
  for (std::size_t k = 0; k < images.size(); ++k) {
    const Image& im = images[k];
    const int x0 = static_cast<int>(k % static_cast<std::size_t>(cols)) * cw + (cw - im.width) / 2;
    const int y0 = static_cast<int>(k / static_cast<std::size_t>(cols)) * ch + (ch - im.height) / 2;
    for (int y = 0; y < im.height; ++y)
      std::memcpy(out.pixel(x0, y0 + y), im.pixel(0, y), static_cast<std::size_t>(im.width) * 4);
  }
  return out;
}

}  // namespace cgamesh::render
