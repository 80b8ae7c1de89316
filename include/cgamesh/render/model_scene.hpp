#pragma once
// A rigged model seen as a Scene: its meshes skinned in a pose, coloured by a mode (the papers'
// figures colour by height or by the influence of one joint), and the skeleton as an overlay.

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/render/scene.hpp"
#include "cgamesh/surgery/surface_index.hpp"

namespace cgamesh::render {

/// How mesh surfaces are coloured.
enum class ColorMode {
  material,  ///< the mesh's base colour (a neutral grey when the model has none)
  height,    ///< world height (y) over the whole scene, blue (low) to red (high)
  normal,    ///< the posed normal as RGB: (n + 1) / 2
  joint,     ///< the influence (skin weight) of one joint, blue (0) to red (1)
  weights,   ///< a colour per joint, blended by the skin weights
  piece,     ///< a colour per connected piece (surgery/pieces.hpp), counted over all models
  generated  ///< vertices made by an operation (cut, tear, drill) in a hot colour, others grey
};

/// The modes by name (a user's choices, in this order; `joint` is "joint:NAME" in text).
inline constexpr std::array<std::pair<std::string_view, ColorMode>, 7> kColorModes{{{"material", ColorMode::material},
                                                                                    {"height", ColorMode::height},
                                                                                    {"normal", ColorMode::normal},
                                                                                    {"joint", ColorMode::joint},
                                                                                    {"weights", ColorMode::weights},
                                                                                    {"piece", ColorMode::piece},
                                                                                    {"new", ColorMode::generated}}};

/// The mode named `name` (material, height, normal, joint, weights, piece, new); "joint:NAME"
/// gives `joint` and sets `joint_name`.
/// @throws InvalidInputError for another name, or "joint:" without a name.
[[nodiscard]] ColorMode parse_color_mode(const std::string& name, std::string& joint_name);

struct ModelSceneOptions {
  ColorMode color = ColorMode::material;
  std::string joint;  ///< ColorMode::joint: the joint's name
  anim::SkinningMode skinning = anim::SkinningMode::cga;
  bool skeleton = false;  ///< joints as dots and bones (joint to parent) as lines, over the mesh
  /// Pulls the pieces of a cut apart for inspection: each connected piece of a mesh
  /// (surgery/pieces.hpp) is moved away from the mesh's centre by `explode` times the offset of
  /// its own centre. 0 draws the model as it is.
  double explode = 0;
};

/// One model placed in one pose.
struct ModelInstance {
  const anim::RiggedModel* model = nullptr;
  anim::Pose pose;
  /// When given (a LiveModel's index), pieces (the piece colours, explode) follow its welds, so
  /// the sides of a cut or tear made in place count apart though they share rest positions.
  const surgery::SurfaceIndex* index = nullptr;
  /// When given, per mesh the #V×3 world positions to draw instead of the skinned ones (a soft
  /// tissue's, soft/tissue.hpp); normals stay the skinned ones.
  const std::vector<mesh::RowMatrixXf<3>>* positions = nullptr;
};

/// The scene of `instances` (e.g. the two pieces of a cut, each in its pose). Positions are
/// skinned with options.skinning; normals, where a mesh has them, are turned by the linear part
/// of each vertex's blended eq. (17) map (anim::skin_normals); meshes without normals are shaded
/// flat. In `material` mode a mesh takes its material's base colour factor and texture (decoded
/// once per model); a mesh whose faces have several materials (Mesh::face_materials: a cut's
/// caps, a hole's walls) is drawn as one DrawMesh per material.
/// @param[out] warnings  if not null, what could not be shown (a texture that does not decode)
///                       and what a texture's decoder repaired (decode_image)
/// @throws InvalidInputError for a null model, a pose that does not fit its skeleton, or a
///         joint name (ColorMode::joint) that a model does not have (the message lists the joints).
[[nodiscard]] Scene model_scene(std::span<const ModelInstance> instances, const ModelSceneOptions& options,
                                std::vector<std::string>* warnings = nullptr);

/// The colour map of the height and joint modes at t in [0, 1] (clamped): blue, cyan, green,
/// yellow, red.
[[nodiscard]] Eigen::Vector3f heat_color(float t) noexcept;

}  // namespace cgamesh::render
