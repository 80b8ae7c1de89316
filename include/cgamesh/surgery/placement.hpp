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

/// The posed surface of every mesh of a model.
struct Placement {
  std::vector<mesh::RowMatrixXf<3>> positions;       ///< per mesh, #V×3 world-space posed positions
  std::vector<anim::SkinningPalette> palettes;       ///< per mesh, the affine map of each palette entry
};

/// Skins every mesh of `model` in `pose` with eq. (17) (`cga` skinning).
/// @throws InvalidInputError when the pose does not fit the skeleton.
[[nodiscard]] Placement place(const anim::RiggedModel& model, const anim::Pose& pose);

}  // namespace cgamesh::surgery
