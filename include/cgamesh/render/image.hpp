#pragma once
// An RGBA8 picture (top row first): PNG encoding, decoding of the images models use as
// textures, contact sheets.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::render {

/// The largest image side: of the pictures render() draws and of the images decode_image()
/// accepts (the common largest OpenGL texture).
inline constexpr int kMaxImageSide = 16384;

/// An 8-bit RGBA image stored row by row, top row first.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  ///< width × height × 4 bytes

  [[nodiscard]] const std::uint8_t* pixel(int x, int y) const noexcept {
    return rgba.data() +
           (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
  }
  [[nodiscard]] std::uint8_t* pixel(int x, int y) noexcept {
    return rgba.data() +
           (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
  }
};

/// @throws InvalidInputError for an empty image or a pixel buffer of the wrong size.
void validate(const Image& image);

/// The PNG encoding of `image` (stb_image_write).
/// @throws InvalidInputError for an empty image or a pixel buffer of the wrong size.
[[nodiscard]] std::string encode_png(const Image& image);

/// Writes `image` as a PNG, all or nothing (io/atomic_file.hpp).
/// @throws InvalidInputError as encode_png(); WriteError when the file cannot be written.
void write_png(const Image& image, const std::filesystem::path& path);

/// Decodes an image held in memory into RGBA8, top row first: a JPEG with libjpeg(-turbo), as
/// browsers do (baseline or progressive; greyscale, YCbCr, RGB or Adobe CMYK/YCCK; damage
/// libjpeg decodes anyway, such as stray bytes before a marker or a truncated scan, is a
/// warning), a PNG, BMP or TGA with stb_image.
/// @param[in] bytes     the encoded image
/// @param[in] what      names the image in messages ("texture 'dwarf.jpg'")
/// @param[out] warnings if not null, gets libjpeg's warnings, each starting with `what`
/// @throws FileError when the bytes do not decode, or declare a side over kMaxImageSide (refused
///         before the pixels are allocated).
[[nodiscard]] Image decode_image(std::span<const std::uint8_t> bytes, const std::string& what,
                                 std::vector<std::string>* warnings = nullptr);

/// The images tiled row by row into one picture of `columns` columns, each cell the size of the
/// largest image; empty cells are filled with `background` (RGB in [0, 1]).
/// @throws InvalidInputError for no images or columns < 1.
/// Why `images` (the pictures of one render) show nothing, or "": when each has one colour
/// only (the background), a warning naming `view` (how the user chose the cameras, e.g. "the
/// view 'front'") and the likely causes.
[[nodiscard]] std::string blank_warning(std::span<const Image> images, const std::string& view);

[[nodiscard]] Image contact_sheet(std::span<const Image> images, int columns, const Eigen::Vector3f& background);

}  // namespace cgamesh::render
