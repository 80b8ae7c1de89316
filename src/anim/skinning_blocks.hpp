#pragma once
// Private to the library: skinning in blocks of 8 vertices across vector lanes, the `vector`,
// `avx2` and `avx512` kernels of anim::SkinningKernel. One source (skinning_blocks.cpp) compiled
// into all three: the baseline x86-64 build, and AVX2 + FMA and AVX-512 builds chosen at run time.

#include <Eigen/Core>

#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::detail {

/// One skinning job's arrays: rows of the mesh's vertices in, rows of `positions` (and
/// `normals`, when not null) out, #V×3 row-major each.
struct BlockJob {
  const mesh::Mesh* mesh;
  const anim::SkinningPalette* palette;
  float* positions;
  float* normals;  ///< null: positions only
  bool streaming;  ///< write the rows with non-temporal stores (anim::SkinningStores::streaming)
};

/// Skins the whole blocks of 8 vertices in [begin, end) and returns the first vertex it left:
/// `end` rounded down to a block, or the start of a block a vector lane cannot do (a blended
/// versor with <V ~V> <= 0), which the caller runs one vertex at a time (and reports).
using BlockKernel = Eigen::Index (*)(const BlockJob& job, Eigen::Index begin, Eigen::Index end);

/// Baseline x86-64 (SSE2) code.
[[nodiscard]] Eigen::Index skin_blocks_vector(const BlockJob& job, Eigen::Index begin, Eigen::Index end);
/// AVX2 + FMA code; call only when cpu_has_avx2_fma().
[[nodiscard]] Eigen::Index skin_blocks_avx2(const BlockJob& job, Eigen::Index begin, Eigen::Index end);
/// AVX2 + FMA + AVX-512 (F, VL, DQ, BW) code on 256-bit vectors; call only when cpu_has_avx512().
[[nodiscard]] Eigen::Index skin_blocks_avx512(const BlockJob& job, Eigen::Index begin, Eigen::Index end);
[[nodiscard]] bool cpu_has_avx2_fma() noexcept;
[[nodiscard]] bool cpu_has_avx512() noexcept;

}  // namespace cgamesh::detail
