#pragma once
// Surface appearance as the model file gives it: materials (glTF's metallic-roughness model, or
// a format's diffuse colour, with their textures) and the images they use, kept encoded as the
// file stores them; and the material of the surfaces surgery makes (caps, hole walls).

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::mesh {

/// An image as the file holds it: PNG or JPEG bytes (embedded, or read from the file next to
/// the model). The bytes are shared and never changed, so that copies of a model (an undo
/// snapshot, the two pieces of a cut) share megabytes of images instead of copying them.
struct TextureImage {
  std::string name;       ///< the file name or the embedded name
  std::string mime_type;  ///< "image/png", "image/jpeg", or empty when unknown
  std::shared_ptr<const std::vector<std::uint8_t>> bytes;  ///< the encoded image, or null

  /// The encoded image (empty when there is none).
  [[nodiscard]] std::span<const std::uint8_t> data() const noexcept {
    return bytes ? std::span<const std::uint8_t>(*bytes) : std::span<const std::uint8_t>();
  }
};

/// How the base colour's alpha is used (glTF material.alphaMode).
enum class AlphaMode { opaque, mask, blend };

/// A material. Texture fields index RiggedModel::textures (−1: none); every texture is sampled
/// with the mesh's texture coordinates (Mesh::uvs, set 0).
struct Material {
  std::string name;
  Eigen::Vector4f base_color{1, 1, 1, 1};  ///< linear RGBA factor (glTF baseColorFactor, or the diffuse colour)
  int base_color_texture = -1;
  /// glTF metallic and roughness factors; formats without them give a dielectric (0, 1).
  float metallic = 0;
  float roughness = 1;
  int metallic_roughness_texture = -1;  ///< roughness in G, metalness in B (glTF)
  int normal_texture = -1;              ///< tangent-space normal map
  float normal_scale = 1;               ///< scale of the normal map's X and Y
  int occlusion_texture = -1;           ///< ambient occlusion in R
  float occlusion_strength = 1;
  Eigen::Vector3f emissive{0, 0, 0};  ///< linear RGB emissive factor
  int emissive_texture = -1;
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;  ///< AlphaMode::mask: alpha below it is transparent
  bool double_sided = false;
};

/// Name of the material of the faces surgery makes to close a surface: the caps of a cut and
/// the walls of a drilled hole.
inline constexpr const char* kCutSurfaceMaterialName = "cgamesh cut surface";

/// The cut-surface material: opaque, single-sided, untextured, a dark flesh red (linear RGBA
/// (0.6, 0.1, 0.1, 1)), dielectric with roughness 0.6 (moist tissue), so that what surgery
/// opened stands out from the model's own surface.
[[nodiscard]] Material cut_surface_material();

/// Index of the cut-surface material in `materials`: the first material named
/// kCutSurfaceMaterialName (so that a model written and loaded again keeps one), else
/// cut_surface_material() appended.
/// @param[in,out] materials  a model's materials (RiggedModel::materials)
[[nodiscard]] int cut_surface_material_index(std::vector<Material>& materials);

}  // namespace cgamesh::mesh
