#pragma once
// Per-vertex blended motors (paper eq. 1-2): M_i = exp(sum_j w_ij log R_j), the common core of
// spline-aligned deformation (section III, w_ij = W_j(lambda_i)) and harmonic-coordinate
// handles (section IV, w_ij = lambda_j(p_i)).
//
// Binding stores p'_i = ~M_i p_i M_i under the rest keys; a frame rebuilds p_i = M_i p'_i ~M_i
// under the posed keys (eq. 2). The keys are TRS versors T(t) R D(s): rigid motors, or motors
// with a uniform dilation.
//
// What exp/log blending of dilating versors means: log V = Br + Bt - (ln s / 2) einf^eo, so the
// blend's scale is the weighted geometric mean prod_j s_j^(w_j) of the key scales, and its
// rotation generator the weighted sum of the key rotation generators. Translation and rotation
// do not blend separately: exp of the summed generator is the flow of x' = (ln s Id + [w]x) x + v,
// a scaling screw, so a region under keys that all equal one versor V (weights summing to 1)
// moves by V exactly, dilation included. Each key blends through its principal log (rotation
// angle in [0, 2 pi)): R and -R are the same rotation but blend differently, the caller picks
// the sign. Weights need not sum to 1; when they do not, the generator is scaled too.

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/exp_log.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

/// The map x -> A x + b of exp(B) for a similarity generator B (cga::exp(B) as a 3x4 matrix,
/// computed without building the versor: one sincos, and an exp only when B dilates).
/// @param[in] b  bivector B = Br + Bt + Bd
/// @return [A b], A = s R
[[nodiscard]] Eigen::Matrix<double, 3, 4> similarity_exp_affine(const cga::SimilarityGenerator<double>& b) noexcept;

/// The principal logs of similarity versors (the generators a blend sums, eq. 1).
/// @param[in] keys  TRS versors
/// @throws InvalidInputError "key j: ..." for a versor that is not a similarity.
[[nodiscard]] std::vector<cga::SimilarityGenerator<double>> similarity_logs(std::span<const cga::Versor<double>> keys);

/// #V x n per-vertex weights, a vertex's weights contiguous.
using WeightMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct MotorBlendOptions {
  int threads = 0;  ///< threads of deform(); 0: all hardware threads
};

class MotorBlend {
 public:
  /// Binds the rest mesh to the keys: p'_i = ~M_i p_i M_i (section III.A).
  /// @param[in] rest       #V x 3 rest positions
  /// @param[in] weights    #V x n blend weights of the n keys
  /// @param[in] rest_keys  #n key versors at rest (TRS: rigid motors, optionally dilating)
  /// @throws InvalidInputError when the sizes disagree, there are no keys, a weight is not
  ///         finite, or a key is not the versor of a similarity.
  MotorBlend(const mesh::RowMatrixXf<3>& rest, WeightMatrix weights, std::span<const cga::Versor<double>> rest_keys,
             const MotorBlendOptions& options = {});

  /// The same with shared weight rows: vertex i blends with `weights.row(rows[i])`. For weights
  /// that take few distinct values (a quantised spline parameter), a frame then computes one
  /// motor per row and costs one table lookup and one 3×4 map per vertex.
  /// @param[in] weights  #R x n weight rows
  /// @param[in] rows     #V row of each vertex
  /// @throws as above, and InvalidInputError for a row out of range.
  MotorBlend(const mesh::RowMatrixXf<3>& rest, WeightMatrix weights, std::vector<int> rows,
             std::span<const cga::Versor<double>> rest_keys, const MotorBlendOptions& options = {});

  [[nodiscard]] Eigen::Index vertex_count() const noexcept { return bound_.rows(); }
  [[nodiscard]] Eigen::Index key_count() const noexcept { return weights_.cols(); }
  /// The weight of key j at vertex i.
  [[nodiscard]] double weight(Eigen::Index i, Eigen::Index j) const noexcept { return weights_(row(i), j); }
  /// #V x 3 the bound points p'_i.
  [[nodiscard]] const mesh::RowMatrixXf<3>& bound_points() const noexcept { return bound_; }

  /// One frame: p_i = M_i p'_i ~M_i with M_i the blend of `keys` (eq. 2), over
  /// options.threads threads (with shared rows: first the motor of each row, then the vertices).
  /// @param[in]  keys  #n posed key versors
  /// @param[out] out   #V x 3 deformed positions (resized)
  /// @throws InvalidInputError when keys has the wrong size or a key is not a similarity.
  void deform(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out) const;

  /// The logs of the keys, computed once per frame for deform_range().
  /// @throws InvalidInputError as deform().
  [[nodiscard]] std::vector<cga::SimilarityGenerator<double>> key_logs(std::span<const cga::Versor<double>> keys) const;
  /// One job of a frame: vertices [begin, end) into the same rows of `out` (#V x 3, sized).
  void deform_range(std::span<const cga::SimilarityGenerator<double>> logs, Eigen::Index begin, Eigen::Index end,
                    mesh::RowMatrixXf<3>& out) const noexcept;

 private:
  [[nodiscard]] Eigen::Index row(Eigen::Index i) const noexcept {
    return rows_.empty() ? i : rows_[static_cast<std::size_t>(i)];
  }
  /// Per weight row, the 3×4 map of its blended motor under `logs`, over the threads.
  [[nodiscard]] std::vector<Eigen::Matrix<float, 3, 4>> row_maps(
      std::span<const cga::SimilarityGenerator<double>> logs) const;
  void bind(const mesh::RowMatrixXf<3>& rest, std::span<const cga::Versor<double>> rest_keys);

  WeightMatrix weights_;
  std::vector<int> rows_;  ///< #V weight row of each vertex; empty: row i for vertex i
  mesh::RowMatrixXf<3> bound_;
  int threads_;
};

}  // namespace cgamesh::deform
