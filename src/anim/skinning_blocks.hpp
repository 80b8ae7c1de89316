#pragma once
// Private to the library: skinning in blocks of 8 vertices across vector lanes, the `vector`,
// `avx2` and `avx512` kernels of anim::SkinningKernel. One source (skinning_blocks.cpp) compiled
// into all three: the baseline x86-64 build, and AVX2 + FMA and AVX-512 builds chosen at run time.

#include <Eigen/Core>

#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::detail {

/// One skinning job's arrays: rest rows in, rows of `positions` (and `normals`, when not null)
/// out, #V×3 row-major each. The rest rows are the mesh's (rest_first 0) or the job's own rows
/// with the frame's morph targets applied, vertex i at row i - rest_first.
struct BlockJob {
  const mesh::Mesh* mesh;  ///< influences
  const anim::SkinningPalette* palette;
  const float* rest_positions;
  const float* rest_normals;  ///< null: positions only
  Eigen::Index rest_first;
  float* positions;
  float* normals;  ///< null: positions only
  bool streaming;  ///< write the rows with non-temporal stores (anim::SkinningStores::streaming)

  [[nodiscard]] const float* rest_position(Eigen::Index i) const noexcept { return rest_positions + 3 * (i - rest_first); }
  [[nodiscard]] const float* rest_normal(Eigen::Index i) const noexcept { return rest_normals + 3 * (i - rest_first); }
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
