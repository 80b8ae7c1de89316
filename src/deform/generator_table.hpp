#pragma once
// Private to the library: the two ends of a motor frame that blends per-vertex weights of key
// generators (FFD eqs. 7–8, cage section VI): the keys' logs as a single-precision table, and
// exp of a vertex's blended generator applied to its rest position.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/exp_log.hpp"
#include "cgamesh/deform/motor_blend.hpp"

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

}  // namespace cgamesh::detail
