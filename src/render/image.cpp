#include "cgamesh/render/image.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <climits>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"

namespace cgamesh::render {
namespace {

void check(const Image& image) {
  if (image.width <= 0 || image.height <= 0)
    throw InvalidInputError("image: empty (" + std::to_string(image.width) + "x" + std::to_string(image.height) + ")");
  if (image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
    throw InvalidInputError("image: " + std::to_string(image.rgba.size()) + " bytes for " +
                            std::to_string(image.width) + "x" + std::to_string(image.height) + " RGBA pixels");
}

std::uint8_t to_byte(float c) { return static_cast<std::uint8_t>(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

}  // namespace

std::string encode_png(const Image& image) {
  check(image);
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

Image decode_image(std::span<const std::uint8_t> bytes, const std::string& what) {
  if (bytes.empty() || bytes.size() > static_cast<std::size_t>(INT_MAX)) throw FileError(what + ": no image data");
  int w = 0, h = 0, channels = 0;
  const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &channels, 4), stbi_image_free);
  if (!pixels) throw FileError(what + ": cannot decode the image (" + stbi_failure_reason() + ")");
  Image out{w, h, {}};
  out.rgba.assign(pixels.get(), pixels.get() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  return out;
}

Image contact_sheet(std::span<const Image> images, int columns, const Eigen::Vector3f& background) {
  if (images.empty()) throw InvalidInputError("contact sheet: no images");
  if (columns < 1) throw InvalidInputError("contact sheet: columns must be >= 1");
  int cw = 0, ch = 0;
  for (const Image& im : images) {
    check(im);
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
