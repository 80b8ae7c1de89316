#pragma once
// Harmonic scalar fields on a triangle mesh (paper section VIII, eq. 14): the discrete
// Laplace-Beltrami equation L lambda = 0 with Dirichlet values on constrained vertices,
// factorised once and solved for many right-hand sides.
//
// Edge weights: mean-value weights w_ij = (tan(a/2) + tan(b/2)) / |p_i - p_j| (a, b the angles
// at p_i next to edge ij), positive for any triangle quality, so the field obeys the maximum
// principle (values stay within the range of the boundary values). They are not symmetric
// (w_ij != w_ji); eq. (14) asks for w_ij = w_ji, so the mean of both directions is used, which
// makes L symmetric positive semi-definite and the free block positive definite (sparse
// Cholesky). Cotangent weights are an option; they can be negative on obtuse triangles, and
// then the maximum principle may fail.
//
// Vertices at exactly the same rest position (seams split for normals or UVs) are one unknown:
// the field cannot tear along a seam.

#include <memory>
#include <span>

#include <Eigen/Core>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

enum class LaplacianWeights { mean_value, cotangent };

struct HarmonicOptions {
  LaplacianWeights weights = LaplacianWeights::mean_value;
};

/// The factorised system of one mesh and one constrained vertex set (move-only).
class HarmonicPrecomputation {
 public:
  struct Impl;
  explicit HarmonicPrecomputation(std::unique_ptr<Impl> impl);
  HarmonicPrecomputation(HarmonicPrecomputation&&) noexcept;
  HarmonicPrecomputation& operator=(HarmonicPrecomputation&&) noexcept;
  ~HarmonicPrecomputation();

  [[nodiscard]] Eigen::Index vertex_count() const noexcept;       ///< #V of the mesh
  [[nodiscard]] Eigen::Index constrained_count() const noexcept;  ///< #C, rows of the boundary values
  [[nodiscard]] const Impl& impl() const noexcept { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// Builds the Laplacian of `mesh` and factorises its free block (eq. 14).
/// @param[in] mesh         #V rest positions and #F faces
/// @param[in] constrained  #C vertex indices with Dirichlet values (welded copies of a
///                         constrained vertex are constrained too)
/// @throws InvalidInputError for an empty constraint set, an index outside [0, #V), a face
///         index outside [0, #V), or a connected component (or isolated vertex) without a
///         constrained vertex (its field would be undetermined);
///         SolverError when the factorisation fails (cotangent weights on a bad mesh).
[[nodiscard]] HarmonicPrecomputation harmonic_precompute(const mesh::Mesh& mesh, std::span<const int> constrained,
                                                         const HarmonicOptions& options = {});

/// Solves for k fields at once.
/// @param[in] pre       from harmonic_precompute
/// @param[in] boundary  #C x k values, row c for constrained[c]
/// @return #V x k fields; constrained vertices hold their values exactly
/// @throws InvalidInputError when boundary is not #C x k, has a non-finite value, or gives two
///         different values to one welded vertex.
[[nodiscard]] Eigen::MatrixXd harmonic_solve(const HarmonicPrecomputation& pre, const Eigen::MatrixXd& boundary);

}  // namespace cgamesh::deform
