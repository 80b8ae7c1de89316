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

#include <array>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

enum class LaplacianWeights {
  mean_value,
  cotangent,          ///< ½(cot α + cot β), negative next to obtuse angles
  clamped_cotangent,  ///< each ½ cot clamped at 0
};

/// The weights by name: mean_value, cotangent, clamped_cotangent.
extern const std::map<std::string, LaplacianWeights> kLaplacianWeights;

struct HarmonicOptions {
  LaplacianWeights weights = LaplacianWeights::mean_value;
};

/// Symmetric edge weights of the non-degenerate triangles of `mesh`, over welded nodes: the
/// off-diagonal of −L (L = D − W, D the row sums), eq. (14).
/// @param[in] mesh        #V rest positions and #F faces
/// @param[in] node        #V node of each vertex (mesh::weld_by_position numbered by
///                        mesh::number_classes), each in [0, node_count)
/// @param[in] node_count  #N
/// @return #N×#N symmetric W (w_ij = w_ji ≥ 0 for mean-value weights)
/// @throws InvalidInputError for a face vertex outside [0, #V).
[[nodiscard]] Eigen::SparseMatrix<double> laplacian_edge_weights(const mesh::Mesh& mesh, std::span<const int> node,
                                                                 int node_count, LaplacianWeights weights);

/// A triangle that carries Laplacian weights: its corners as welded nodes, and ½ cot of the
/// angle at each corner, the weight of the opposite edge (corners c+1, c+2).
struct CotangentTriangle {
  std::array<int, 3> node;
  std::array<double, 3> half_cot;
};
/// The triangles of `mesh` that laplacian_edge_weights() weighs (three distinct nodes, non-zero
/// area), in face order: summing half_cot over them gives its cotangent weights.
/// @param[in] mesh     #V rest positions and #F faces
/// @param[in] node     #V node of each vertex, as laplacian_edge_weights() takes it
/// @param[in] clamped  each ½ cot clamped at 0
/// @throws InvalidInputError for a face vertex outside [0, #V).
[[nodiscard]] std::vector<CotangentTriangle> cotangent_triangles(const mesh::Mesh& mesh, std::span<const int> node,
                                                                 bool clamped);

/// The factorised system of one mesh and one constrained vertex set (libigl's
/// min_quad_with_fixed_data): the free rows solve L_ff x_f = W_fc x_c. Move-only.
struct HarmonicPrecomputation {
  using SparseMatrix = Eigen::SparseMatrix<double>;
  std::vector<int> node_of_vertex;   ///< #V welded node of each vertex
  std::vector<int> slot_of_node;     ///< #N free index (≥ 0), or −1 − the constrained node's index
  std::vector<int> constrained;      ///< #C constrained vertex indices as given
  int constrained_nodes = 0;         ///< distinct constrained nodes
  SparseMatrix free_by_constrained;  ///< W_fc (free × constrained nodes)
  /// L_ff factorised; null when every node is constrained. (Eigen's solvers cannot be moved.)
  std::unique_ptr<Eigen::SimplicialLDLT<SparseMatrix>> ldlt;

  [[nodiscard]] Eigen::Index vertex_count() const noexcept {  ///< #V of the mesh
    return static_cast<Eigen::Index>(node_of_vertex.size());
  }
  [[nodiscard]] Eigen::Index constrained_count() const noexcept {  ///< #C, rows of the boundary values
    return static_cast<Eigen::Index>(constrained.size());
  }
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

/// The boundary values per constrained node (the order of the columns of free_by_constrained).
/// @param[in] pre       from harmonic_precompute
/// @param[in] boundary  #C x k values, row c for constrained[c]
/// @return (distinct constrained nodes) x k
/// @throws InvalidInputError when boundary is not #C x k, has a non-finite value, or gives two
///         different values to one welded vertex.
[[nodiscard]] Eigen::MatrixXd constrained_node_values(const HarmonicPrecomputation& pre,
                                                      const Eigen::MatrixXd& boundary);

/// Solves for k fields at once.
/// @param[in] pre       from harmonic_precompute
/// @param[in] boundary  #C x k values, row c for constrained[c]
/// @return #V x k fields; constrained vertices hold their values exactly
/// @throws InvalidInputError when boundary is not #C x k, has a non-finite value, or gives two
///         different values to one welded vertex.
[[nodiscard]] Eigen::MatrixXd harmonic_solve(const HarmonicPrecomputation& pre, const Eigen::MatrixXd& boundary);

}  // namespace cgamesh::deform
