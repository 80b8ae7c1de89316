#pragma once
// The pose a surgical tool is placed against. Tools act on the posed (skinned, world-space)
// surface; new vertices get rest positions from the same edge/face parameters on the rest mesh,
// so the result is again a rest mesh + skin that re-animates (paper section 4.2).

#include <vector>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::surgery {

/// Which predicates a surgery operation evaluates: CGA (X·Π of conformal points and planes,
/// the paper's choice) or the equivalent Euclidean formulas (n·x − d), kept to measure the
/// cost of GA as the paper's Table 1 does. Both give the same result.
enum class Predicates { cga, euclidean };

/// Where a new vertex (a point on an old edge or inside an old face) goes in the rest mesh.
enum class RestPosition {
  /// The point that its blended skin map Σ wₙ Aₙ (with its new weights, eq. 17) takes onto its
  /// placed position: re-posed at the operation's pose, it lies on the tool (beyond the paper).
  /// Where that map cannot be inverted, the parametric position.
  exact,
  /// The same edge/face parameters on the rest mesh (paper section 4.2): skinning is not
  /// linear in (weights, position) together, so re-posed it drifts off the tool.
  parametric,
};

/// How far a tool may reach, in diagonals of the placed model's bounding box: cut, tear and
/// drill refuse (InvalidInputError) a tool point farther than this from the box, or a drill
/// radius larger than this, since such values make no geometric sense for the model (and their
/// arithmetic loses every digit of the model's coordinates).
inline constexpr double kMaxToolReach = 1e6;

/// The posed surface of every mesh of a model.
struct Placement {
  std::vector<mesh::RowMatrixXf<3>> positions;  ///< per mesh, #V×3 world-space posed positions
  std::vector<anim::SkinningPalette> palettes;  ///< per mesh, the affine map of each palette entry
};

/// Per mesh of `model`, its `cga` palette in `pose` (eq. (17)'s maps, with the pose's morph
/// weights): what place() skins with.
/// @throws InvalidInputError when the pose does not fit the skeleton.
[[nodiscard]] std::vector<anim::SkinningPalette> palettes(const anim::RiggedModel& model, const anim::Pose& pose);

/// Skins every mesh of `model` in `pose` with eq. (17) (`cga` skinning).
/// @throws InvalidInputError when the pose does not fit the skeleton.
[[nodiscard]] Placement place(const anim::RiggedModel& model, const anim::Pose& pose);

/// The normals of place()'s surface: every mesh's normals skinned in `pose` with the same `cga`
/// palettes (anim::skin_normals()), e.g. for an OBJ or PLY of a surgery result as placed.
/// @return per mesh, #V×3 unit normals, or 0 rows for a mesh without normals
/// @throws InvalidInputError when the pose does not fit the skeleton.
[[nodiscard]] std::vector<mesh::RowMatrixXf<3>> placed_normals(const anim::RiggedModel& model, const anim::Pose& pose);

}  // namespace cgamesh::surgery
