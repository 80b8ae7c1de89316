#include "cgamesh/anim/pose_choice.hpp"

#include <cmath>

#include "cgamesh/errors.hpp"
#include "cgamesh/number_text.hpp"

namespace cgamesh::anim {
ChosenPose choose_pose(const RiggedModel& model, const PoseRequest& request) {
  const int clips = static_cast<int>(model.clips.size());
  if (request.clip < -1 || request.clip >= clips)
    throw InvalidInputError("clip " + std::to_string(request.clip) + ": the model has " + std::to_string(clips) +
                            (clips == 1 ? " clip" : " clips"));
  if (request.time && (!std::isfinite(*request.time) || *request.time < 0))
    throw InvalidInputError("time " + number_text(*request.time) + ": it must be a finite number >= 0");
  ChosenPose out;
  out.clip = request.clip;
  if (out.clip < 0 && request.time) {
    if (clips == 0)
      out.warnings.push_back("time " + number_text(*request.time) + " s: the model has no animation; the bind pose is used");
    else
      out.clip = 0;
  }
  if (out.clip < 0) {
    out.pose = rest_pose(model.skeleton);
  } else {
    const Clip& c = model.clips[static_cast<std::size_t>(out.clip)];
    out.time = request.time.value_or(0.0);
    if (out.time > c.duration)
      out.warnings.push_back("time " + number_text(out.time) + " s is past the end of clip '" + c.name + "' (" +
                             number_text(c.duration) + " s): its last pose is used");
    out.pose = sample(model.skeleton, c, out.time, request.blend);
  }
  apply_edits(out.pose, request.edits);
  for (const MorphSetting& m : request.morphs) set_morph_weight(out.pose, model.meshes, m.target, m.weight);
  return out;
}

}  // namespace cgamesh::anim
