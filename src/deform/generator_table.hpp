#pragma once
// Private to the library: the two ends of a motor frame that blends per-vertex weights of key
// generators (FFD eqs. 7–8, cage section VI): the keys' logs as a single-precision table, and
// exp of a vertex's blended generator applied to its rest position — one vertex at a time in
// double (the reference), or a block of vertices at a time in single precision, laid out for the
// vector units (what a frame runs).

#include <algorithm>
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/exp_log.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::detail {

using Generator = cga::SimilarityGenerator<double>;
inline constexpr int kGeneratorSize = static_cast<int>(Generator::size);

/// The principal logs of `motors`, one column each, in single precision (7 digits, as the
/// positions): what a frame contracts with each vertex's weights.
/// @param[out] table  kGeneratorSize × #motors (resized); any Eigen float matrix layout
/// @throws InvalidInputError as similarity_logs().
template <class Table>
void fill_log_table(std::span<const cga::Versor<double>> motors, Table& table) {
  const std::vector<Generator> generators = deform::similarity_logs(motors);
  table.resize(kGeneratorSize, static_cast<Eigen::Index>(generators.size()));
  for (std::size_t c = 0; c < generators.size(); ++c)
    for (int k = 0; k < kGeneratorSize; ++k)
      table(k, static_cast<Eigen::Index>(c)) = static_cast<float>(generators[c][static_cast<std::size_t>(k)]);
}

/// exp(B) p: a vertex's blended generator B applied to its rest position p (eq. 7).
inline Eigen::RowVector3f exp_apply(const Eigen::Matrix<float, kGeneratorSize, 1>& b,
                                    const Eigen::RowVector3f& p) noexcept {
  std::array<double, Generator::size> coefficients{};
  for (int k = 0; k < kGeneratorSize; ++k) coefficients[static_cast<std::size_t>(k)] = b[k];
  const Eigen::Matrix<double, 3, 4> m = deform::similarity_exp_affine(Generator(coefficients));
  return (m.leftCols<3>() * p.transpose().cast<double>() + m.col(3)).transpose().cast<float>();
}

/// Blended generators of up to kBlock consecutive vertices, component-major: one vector load per
/// component covers several vertices.
inline constexpr int kBlock = 16;
struct GeneratorBlock {
  alignas(64) float c[kGeneratorSize][kBlock] = {};  ///< c[k][lane]: component k (storage order)
};

/// The instruction sets exp_apply_block() is compiled for.
enum class Isa {
  baseline,   ///< what the build targets (SSE2 on any x86-64)
  x86_64_v3,  ///< AVX2 and FMA (x86-64 builds only)
};
/// Whether this CPU runs `isa`'s variant.
[[nodiscard]] bool has_isa(Isa isa) noexcept;

/// exp(B) p for the first `count` (≤ kBlock) lanes of `b`, p from `rest` into `out` (both
/// row-major count×3): exp_apply() in single precision, with a polynomial sincos and no branch
/// per vertex; a lane whose generator dilates (B has an einf^eo part) takes exp_apply(). The
/// variant of the best instruction set the CPU has, or of `isa` (which has_isa() must allow).
void exp_apply_block(const GeneratorBlock& b, int count, const float* rest, float* out) noexcept;
void exp_apply_block(const GeneratorBlock& b, int count, const float* rest, float* out, Isa isa) noexcept;

/// A motor frame's vertices [begin, end): out.row(i) = exp(generator(i)) rest.row(i), with
/// generator(i) vertex i's blended generator (a float vector of kGeneratorSize), block by block.
template <class Blend>
void exp_apply_range(const mesh::RowMatrixXf<3>& rest, Eigen::Index begin, Eigen::Index end, mesh::RowMatrixXf<3>& out,
                     Blend&& generator) {
  GeneratorBlock block;
  for (Eigen::Index first = begin; first < end; first += kBlock) {
    const int count = static_cast<int>(std::min<Eigen::Index>(kBlock, end - first));
    for (int lane = 0; lane < count; ++lane) {
      const Eigen::Matrix<float, kGeneratorSize, 1> g = generator(first + lane);
      for (int k = 0; k < kGeneratorSize; ++k) block.c[k][lane] = g[k];
    }
    exp_apply_block(block, count, &rest(first, 0), &out(first, 0));
  }
}

}  // namespace cgamesh::detail
