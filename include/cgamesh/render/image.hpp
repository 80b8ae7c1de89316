#pragma once
// An RGBA8 picture (top row first), PNG encoding and contact sheets.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::render {

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

/// The PNG encoding of `image` (stb_image_write).
/// @throws InvalidInputError for an empty image or a pixel buffer of the wrong size.
[[nodiscard]] std::string encode_png(const Image& image);

/// Writes `image` as a PNG, all or nothing (io/atomic_file.hpp).
/// @throws InvalidInputError as encode_png(); WriteError when the file cannot be written.
void write_png(const Image& image, const std::filesystem::path& path);

/// Decodes a PNG, JPEG, BMP or TGA held in memory (stb_image) into RGBA8, top row first.
/// @param[in] what  names the image in error messages
/// @throws FileError when the bytes are not an image stb_image can decode.
[[nodiscard]] Image decode_image(std::span<const std::uint8_t> bytes, const std::string& what);

/// The images tiled row by row into one picture of `columns` columns, each cell the size of the
/// largest image; empty cells are filled with `background` (RGB in [0, 1]).
/// @throws InvalidInputError for no images or columns < 1.
[[nodiscard]] Image contact_sheet(std::span<const Image> images, int columns, const Eigen::Vector3f& background);

}  // namespace cgamesh::render
