#pragma once
// Values written as text, as the command line, viewer scripts and Python share them:
// comma-separated numbers, joint edits ("JOINT:rotate=AX,AY,AZ,DEG"), clips by name or index,
// blend and skinning modes by name.

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"

namespace cgamesh::io {

/// Blend modes by name: format, linear, log.
extern const std::map<std::string, anim::BlendMode> kBlendModes;
/// Skinning modes by name: cga, versor, matrix, dqs.
extern const std::map<std::string, anim::SkinningMode> kSkinningModes;

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

/// World-space positions of every mesh in `pose`.
[[nodiscard]] std::vector<mesh::RowMatrixXf<3>> posed_positions(const anim::RiggedModel& model, const anim::Pose& pose,
                                                                anim::SkinningMode mode);

}  // namespace cgamesh::io
