#pragma once
// Keyframes generated on the fly (paper section 4): the user gives poses at times, the frames
// between them come from blending the joints' versors, and the result is a new clip.

#include <span>
#include <string>
#include <vector>

#include "cgamesh/anim/clip.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skeleton.hpp"

namespace cgamesh::anim {

/// A user pose at a time: the rest pose with edits applied.
struct Keyframe {
  double time = 0;  ///< seconds
  std::vector<JointEdit> edits;
};

/// The most frames generate_clip() bakes into one clip ((last − first key time) · fps + 1):
/// about 55 minutes at 30 fps; more is refused rather than filling memory.
inline constexpr double kMaxGeneratedFrames = 100000;

struct KeyframeOptions {
  BlendMode blend = BlendMode::linear;  ///< linear (the paper's choice here) or log
  double fps = 30;                      ///< frames per second of the generated clip
  std::string name = "generated";
};

/// Bakes a clip: at `fps` frames per second between the first and last keyframe, every joint's
/// local versor is blended between the two surrounding keyframes (lerp renormalised, or log
/// blend) and stored as LINEAR translation/rotation/scale keys; joints no keyframe edits are
/// left out.
/// @param[in] keyframes  at least two, with strictly increasing times
/// @throws InvalidInputError for fewer than two keyframes, times not increasing, fps <= 0,
///         more than kMaxGeneratedFrames frames, BlendMode::format, a bad edit, or a frame
///         whose transform is not finite (an edit that overflows).
[[nodiscard]] Clip generate_clip(const Skeleton& skeleton, std::span<const Keyframe> keyframes,
                                 const KeyframeOptions& options = {});

}  // namespace cgamesh::anim
