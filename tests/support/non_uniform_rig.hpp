#pragma once
// A rig that is not made of similarities, from the shipped RiggedSimple.glb: its clip scales
// both joints non-uniformly (the child under its parent's stretch shears), its root has a
// non-uniform rest scale, and the child's inverse bind stretches. Blender exports with scale
// tracks look like this; no versor holds such joint maps.

#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "anim/model_fixtures.hpp"
#include "support/gltf_edit.hpp"

namespace cgamesh_test {

namespace detail {

/// Multiplies the `count` floats of accessor `a` from its element e on (every `width` floats)
/// by f(e, component).
template <class F>
void scale_floats(tinygltf::Model& m, int a, int width, F&& f) {
  const tinygltf::Accessor& acc = m.accessors[static_cast<std::size_t>(a)];
  const tinygltf::BufferView& view = m.bufferViews[static_cast<std::size_t>(acc.bufferView)];
  ASSERT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  ASSERT_TRUE(view.byteStride == 0 || view.byteStride == static_cast<std::size_t>(4 * width));
  unsigned char* data = m.buffers[static_cast<std::size_t>(view.buffer)].data.data() + view.byteOffset + acc.byteOffset;
  for (std::size_t e = 0; e < acc.count; ++e)
    for (int c = 0; c < width; ++c) {
      float v = 0;
      std::memcpy(&v, data + 4 * (e * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)), 4);
      v *= static_cast<float>(f(e, c));
      std::memcpy(data + 4 * (e * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)), &v, 4);
    }
}

}  // namespace detail

/// Writes the non-uniformly scaled RiggedSimple into `dir` and returns its path.
inline std::filesystem::path non_uniform_simple(const std::filesystem::path& dir) {
  tinygltf::Model m = read_glb(asset("RiggedSimple.glb"));
  const tinygltf::Animation& clip = m.animations.at(0);
  for (const tinygltf::AnimationChannel& c : clip.channels) {
    if (c.target_path != "scale") continue;
    const int out = clip.samplers[static_cast<std::size_t>(c.sampler)].output;
    const double n = static_cast<double>(m.accessors[static_cast<std::size_t>(out)].count - 1);
    // Key k of n: the root stretches along y and squeezes along z, the child the other way round
    // along x and z, more at each key.
    const bool root = c.target_node == m.skins[0].joints[0];
    detail::scale_floats(m, out, 3, [&](std::size_t k, int axis) {
      const double a = static_cast<double>(k + 1) / (n + 1);
      const double root_factors[3] = {1, 1 + 0.8 * a, 1 - 0.4 * a}, child_factors[3] = {1 + 0.6 * a, 1, 1 - 0.3 * a};
      return root ? root_factors[axis] : child_factors[axis];
    });
  }
  m.nodes[static_cast<std::size_t>(m.skins[0].joints[0])].scale = {1.0, 1.5, 0.75};
  // The child's inverse bind: mesh space stretched into its joint space, diag(1.3, 1, 0.8) B.
  detail::scale_floats(m, m.skins[0].inverseBindMatrices, 16, [](std::size_t joint, int i) {
    const double rows[4] = {1.3, 1, 0.8, 1};
    return joint == 1 ? rows[i % 4] : 1.0;
  });
  return write_glb(m, dir / "RiggedSimpleNonUniform.glb");
}

}  // namespace cgamesh_test
