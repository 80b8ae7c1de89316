#pragma once
// Values written as text, as the command line, viewer scripts and Python share them:
// comma-separated numbers, joint edits ("JOINT:rotate=AX,AY,AZ,DEG"), clips by name or index,
// blend and skinning modes by name.

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/io/model_writer.hpp"

namespace cgamesh::io {

/// Blend modes by name: format, linear, log.
extern const std::map<std::string, anim::BlendMode> kBlendModes;
/// The blend modes a generated clip's keys take (linear, log): kBlendModes but the file's own.
extern const std::map<std::string, anim::BlendMode> kKeyframeBlendModes;
/// Skinning modes by name: cga, versor, matrix, dqs.
extern const std::map<std::string, anim::SkinningMode> kSkinningModes;
/// Rest positions of surgery's new vertices by name: exact, parametric.
extern const std::map<std::string, surgery::RestPosition> kRestPositions;
/// Surgery's predicates by name: cga, euclidean.
extern const std::map<std::string, surgery::Predicates> kPredicates;

/// The value named `name` in `names` (one of the tables above).
/// @throws InvalidInputError naming `what` and listing the names there are.
template <class T>
[[nodiscard]] T value_by_name(const std::map<std::string, T>& names, const std::string& name, const std::string& what) {
  const auto it = names.find(name);
  if (it != names.end()) return it->second;
  std::string list;
  for (const auto& entry : names) list += (list.empty() ? "" : ", ") + entry.first;
  throw InvalidInputError(what + " '" + name + "': expected one of " + list);
}

/// The farthest a joint edit may translate or scale, in model sizes: values beyond make no
/// geometric sense and overflow floats.
inline constexpr double kMaxReach = 1e6;

/// `x` as printed by an ostream (6 significant digits): for messages.
[[nodiscard]] std::string number(double x);

/// Exactly `count` comma-separated finite numbers (denormals included).
/// @throws InvalidInputError naming `what` otherwise.
[[nodiscard]] std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what);

/// The joint named `name`.
/// @throws InvalidInputError for an unknown joint, listing the skeleton's joints.
[[nodiscard]] int joint_index(const anim::Skeleton& skeleton, const std::string& name);

/// "JOINT:rotate=AX,AY,AZ,DEG" | "JOINT:translate=X,Y,Z" | "JOINT:scale=S". A rotation axis
/// may have any non-zero length; a translation longer than `max_translation`, or a scale
/// outside [1/kMaxReach, kMaxReach], is refused.
/// @throws InvalidInputError for an unknown joint (naming the valid ones), a malformed edit, a
///         zero axis or a translation out of reach.
[[nodiscard]] anim::JointEdit parse_edit(const anim::Skeleton& skeleton, const std::string& text,
                                         double max_translation = INFINITY);

/// "TARGET=W": morph target TARGET (a name; the last '=' ends it) at weight W.
/// @throws InvalidInputError for a missing '=' or name, or a weight that is no finite number.
[[nodiscard]] anim::MorphSetting parse_morph_setting(const std::string& text);

/// The farthest an edit may translate a joint in `model`: kMaxReach times the diagonal of its
/// bind-pose box.
[[nodiscard]] double max_translation(const anim::RiggedModel& model);

/// The clip named or numbered `anim`.
/// @throws InvalidInputError naming the valid clips when there is no such clip.
[[nodiscard]] int clip_index(const anim::RiggedModel& model, const std::string& anim);

/// The names of the clips of `model`, in order.
[[nodiscard]] std::vector<std::string> clip_names(const anim::RiggedModel& model);

/// The name of `mode` in kBlendModes.
[[nodiscard]] std::string blend_name(anim::BlendMode mode);
/// The name of `mode` in kSkinningModes.
[[nodiscard]] std::string skinning_name(anim::SkinningMode mode);

/// World-space positions of every mesh in `pose`.
[[nodiscard]] std::vector<mesh::RowMatrixXf<3>> posed_positions(const anim::RiggedModel& model, const anim::Pose& pose,
                                                                anim::SkinningMode mode);

/// One posed frame of a model in world space, per mesh of the model: what posed_frame() gives
/// and what a static file of the frame (OBJ, PLY, glTF) holds.
struct PosedFrame : mesh::WorldSurface {
  // positions: per mesh, #V×3 posed positions; normals: per mesh, #V×3 unit skinned normals, or
  // 0 rows without normals.
  /// versor and dqs on a rig whose joint maps are not all similarities (non-uniform scale or
  /// shear, anim::maps_by_similarities()): the largest distance of a posed vertex from the exact
  /// skinning of this pose (cga, matrix), in model units (anim::exact_displacement()); else 0.
  double displacement = 0;
  /// What the skinning approximated in this pose (the displacement above), for the user.
  std::vector<std::string> warnings;
};

/// World-space positions and normals of every mesh in `pose`: the positions are
/// posed_positions(), the normals anim::skin_normals() of the same palette (the rest normals
/// turned by the linear part of each vertex's blended transform), so that they fit the posed
/// surface. A mesh without normals gets 0 normal rows. In versor and dqs mode a rig whose joint
/// maps are not all similarities is skinned once more exactly, for PosedFrame::displacement.
/// @param[in] model  the model; a mesh's normals are #V×3 or 0 rows
/// @param[in] pose   a pose of model.skeleton (one local transform per joint)
/// @param[in] mode   the skinning of both positions and normals
/// @throws InvalidInputError when a skin names a joint the pose does not have
///         (anim::make_palette), or a mesh has a normal row count other than 0 or #V.
[[nodiscard]] PosedFrame posed_frame(const anim::RiggedModel& model, const anim::Pose& pose, anim::SkinningMode mode);

}  // namespace cgamesh::io
