#pragma once
// Animation clips: per-joint translation, rotation and scale keys and the morph-target weights
// of the meshes on a node, as files store them.

#include <string>
#include <vector>

namespace cgamesh::anim {

/// How the file says to interpolate between keys (glTF sampler.interpolation).
enum class Interpolation { step, linear, cubic_spline };
/// Which part of the joint's TRS a channel drives, or the morph weights of the meshes on it.
enum class ChannelPath { translation, rotation, scale, weights };

/// Keys of one TRS component of one joint, or of the morph weights of the meshes on that joint
/// (node; glTF's "weights" path).
struct Channel {
  int joint = -1;  ///< skeleton joint index
  ChannelPath path = ChannelPath::translation;
  Interpolation interpolation = Interpolation::linear;
  std::vector<double> times;  ///< #K strictly increasing seconds
  /// Flat key values: 3 per key (x y z) for translation/scale, 4 (x y z w) for rotation,
  /// weight_count for weights; for cubic_spline each key holds in-tangent, value, out-tangent in
  /// that order (glTF layout).
  std::vector<double> values;
  int weight_count = 0;  ///< weights: the number of morph targets of the meshes on the joint

  [[nodiscard]] int components() const noexcept {
    return path == ChannelPath::rotation ? 4 : path == ChannelPath::weights ? weight_count : 3;
  }
};

struct Clip {
  std::string name;
  /// Seconds: the length the file declares or, when longer, the largest key time. Past a
  /// channel's last key its last value holds (the glTF writer keys that hold to the end).
  double duration = 0;
  std::vector<Channel> channels;
};

}  // namespace cgamesh::anim
