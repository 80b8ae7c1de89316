#pragma once
// Surface appearance as the model file gives it: materials (base colour factor and texture,
// glTF's metallic-roughness model or a format's diffuse colour) and the images they use, kept
// encoded as the file stores them.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::mesh {

/// An image as the file holds it: PNG or JPEG bytes (embedded, or read from the file next to
/// the model).
struct TextureImage {
  std::string name;       ///< the file name or the embedded name
  std::string mime_type;  ///< "image/png", "image/jpeg", or empty when unknown
  std::vector<std::uint8_t> bytes;
};

struct Material {
  std::string name;
  Eigen::Vector4f base_color{1, 1, 1, 1};  ///< linear RGBA factor (glTF baseColorFactor, or the diffuse colour)
  int base_color_texture = -1;             ///< index into RiggedModel::textures, or -1
  /// glTF metallic and roughness factors; formats without them give a dielectric (0, 1).
  float metallic = 0;
  float roughness = 1;
  bool double_sided = false;
};

}  // namespace cgamesh::mesh
