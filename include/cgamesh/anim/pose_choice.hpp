#pragma once
// Choosing the pose a front end acts on from a clip, a time, a blend, joint edits and morph
// weights: one set of rules for the CLI, the viewer's replay commands, Python and the C ABI.

#include <optional>
#include <string>
#include <vector>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"

namespace cgamesh::anim {

/// What the user asked for. Nothing given: the bind pose.
struct PoseRequest {
  int clip = -1;                ///< a clip of the model, or −1: none named
  std::optional<double> time;   ///< seconds into the clip (0 when a clip is named without a time)
  BlendMode blend = BlendMode::format;
  std::vector<JointEdit> edits;      ///< applied after the clip (apply_edits)
  std::vector<MorphSetting> morphs;  ///< morph weights by target name, over the clip's
};

/// The pose chosen, and what the user should know about the choice.
struct ChosenPose {
  Pose pose;
  int clip = -1;    ///< the clip sampled, −1 for the bind pose
  double time = 0;  ///< the time it was sampled at
  /// A time past the clip's end (its last pose is used), a time on a model without clips (the
  /// bind pose is used).
  std::vector<std::string> warnings;
};

/// The pose `request` asks of `model`: the bind pose when it names neither a clip nor a time;
/// clip `request.clip` (or the first clip when only a time is given) sampled at the time (0 by
/// default) with the blend; then the edits and the morph weights.
/// @throws InvalidInputError for a clip out of range, a negative or non-finite time, an edit of
///         an unknown joint or a degenerate one (apply_edits), an unknown morph target.
[[nodiscard]] ChosenPose choose_pose(const RiggedModel& model, const PoseRequest& request);

}  // namespace cgamesh::anim
