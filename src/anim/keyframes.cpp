#include "cgamesh/anim/keyframes.hpp"

#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include "cgamesh/cga/interpolation.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/number_text.hpp"

namespace cgamesh::anim {

Clip generate_clip(const Skeleton& skeleton, std::span<const Keyframe> keyframes, const KeyframeOptions& options) {
  if (keyframes.size() < 2) throw InvalidInputError("keyframes: need at least two keyframes");
  if (!(options.fps > 0) || !std::isfinite(options.fps)) throw InvalidInputError("keyframes: fps must be > 0");
  if (options.blend == BlendMode::format)
    throw InvalidInputError("keyframes: generated frames blend linearly or logarithmically, not 'format'");
  std::set<int> edited;
  std::vector<Pose> poses;
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const Keyframe& key = keyframes[k];
    if (!std::isfinite(key.time) || (k > 0 && !(key.time > keyframes[k - 1].time)))
      throw InvalidInputError("keyframes: times must be finite and strictly increasing");
    poses.push_back(rest_pose(skeleton));
    apply_edits(poses.back(), key.edits);
    for (const JointEdit& e : key.edits) edited.insert(e.joint);
  }

  Clip clip;
  clip.name = options.name;
  const double t0 = keyframes.front().time, t1 = keyframes.back().time;
  clip.duration = t1;
  const double frame_count = std::ceil((t1 - t0) * options.fps - 1e-9) + 1;
  if (!(frame_count <= kMaxGeneratedFrames))
    throw InvalidInputError("keyframes: " + number_text(t1 - t0) + " s at " + number_text(options.fps) + " fps makes " +
                            number_text(frame_count) + " frames, more than the " + number_text(kMaxGeneratedFrames) +
                            " a generated clip may hold");
  const auto frames = static_cast<std::size_t>(frame_count);
  for (int j : edited) {
    Channel ct, cr, cs;
    ct.path = ChannelPath::translation;
    cr.path = ChannelPath::rotation;
    cs.path = ChannelPath::scale;
    ct.joint = cr.joint = cs.joint = j;
    std::size_t seg = 0;
    Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
    for (std::size_t f = 0; f < frames; ++f) {
      const double t = std::min(t0 + static_cast<double>(f) / options.fps, t1);
      while (seg + 2 < keyframes.size() && t > keyframes[seg + 1].time) ++seg;
      const double a = (t - keyframes[seg].time) / (keyframes[seg + 1].time - keyframes[seg].time);
      const cga::Versor<double>& v0 = poses[seg].local_versors[j];
      cga::Versor<double> v1 = poses[seg + 1].local_versors[j];
      if (cga::scalar_product(v0, cga::reverse(v1)) < 0) v1 = -v1;  // V and -V: blend the short way
      const cga::Versor<double> v =
          options.blend == BlendMode::linear ? cga::lerp_normalized(v0, v1, a) : cga::log_blend(v0, v1, a);
      const Transform tr = Transform::from_versor(v);
      if (!tr.translation.allFinite() || !tr.rotation.coeffs().allFinite() || !tr.scale.allFinite())
        throw InvalidInputError("keyframes: the frame at t = " + std::to_string(t) + " of joint '" +
                                std::string(skeleton.names()[j]) + "' is not finite (an edit overflows)");
      for (Channel* c : {&ct, &cr, &cs}) c->times.push_back(t);
      ct.values.insert(ct.values.end(), {tr.translation.x(), tr.translation.y(), tr.translation.z()});
      Eigen::Quaterniond q = tr.rotation;
      // Consecutive quaternions on one side, so LINEAR (slerp) keys replay the same path.
      if (f > 0 && previous.dot(q) < 0) q.coeffs() = -q.coeffs();
      previous = q;
      cr.values.insert(cr.values.end(), {q.x(), q.y(), q.z(), q.w()});
      cs.values.insert(cs.values.end(), {tr.scale.x(), tr.scale.y(), tr.scale.z()});
      if (t >= t1) break;
    }
    clip.channels.push_back(std::move(ct));
    clip.channels.push_back(std::move(cr));
    clip.channels.push_back(std::move(cs));
  }
  return clip;
}

}  // namespace cgamesh::anim
