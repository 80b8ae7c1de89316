#pragma once
// Private to the library: a SkinningPalette's entries packed for the vector kernels
// (skinning_blocks.cpp), which make_palette() builds along with the public entries.

#include <cstddef>
#include <span>

#include "cgamesh/anim/skinning.hpp"

namespace cgamesh::detail {

/// The packed entries of a palette, `stride()` floats per palette entry:
///   cga, matrix - the columns of [A b], each padded to 4 floats (16);
///   versor - the motor's 8 or the versor's 16 coefficients in storage order;
///   dqs - the dual quaternion's 8, then (when `scales` is not empty) the 9 of S column-major (17).
struct PackedPalette {
  /// The largest stride: room for that many floats per entry never reallocates.
  static constexpr int kMaxStride = 17;

  /// Packs the entries of `p.mode` (affine, motors or versors, dual quaternions and scales) and
  /// sets the stride; once per palette.
  static void pack(anim::SkinningPalette& p);
  /// Makes room for `entries` palette entries at the largest stride (one allocation per frame).
  static void reserve(anim::SkinningPalette& p, std::size_t entries) {
    p.packed_.reserve(static_cast<std::size_t>(kMaxStride) * entries);
  }

  /// #entries × stride() floats.
  [[nodiscard]] static std::span<const float> entries(const anim::SkinningPalette& p) noexcept { return p.packed_; }
  /// Floats per palette entry; 0 before pack().
  [[nodiscard]] static int stride(const anim::SkinningPalette& p) noexcept { return p.packed_stride_; }
};

}  // namespace cgamesh::detail
