#pragma once
// As-rigid-as-possible surface modelling with rotors (paper section VII; Sorkine & Alexa 2007):
// minimise Σᵢ Σ_{(j,k) ∈ Cᵢ} w_jk ‖(p′_j − p′_k) − Mᵢ (p_j − p_k) M̃ᵢ‖² (eqs. 9–11) over the
// deformed positions p′ and one rotor Mᵢ per vertex, with handle vertices fixed, by alternating
//  - the local step: each cell's optimal rotation from its covariance S (eq. 11: the top
//    eigenvector of Horn's symmetric 4×4 matrix P, a quaternion = the rotor; or the 3×3 SVD as
//    the reference), and
//  - the global step: the Poisson system ΔP′ = C (eq. 12) with the handle rows substituted,
//    factorised once per handle set; three right-hand sides (x, y, z) per iteration.
// The precompute/solve pair follows libigl's arap_precompute / arap_solve.
//
// Weights: the cotangent weights ½(cot α + cot β), unclamped by default as Sorkine–Alexa and
// libigl use them (results comparable with theirs); negative next to obtuse angles. Cells
// (ArapEnergy): `spokes` is the paper's one-ring of edges at each vertex (eq. 9);
// `spokes_and_rims` (libigl's default for surfaces) adds the opposite edge of every triangle at
// the vertex. Both give the same Laplacian; measured on the cow (579 negative weights), `spokes`
// stretches edges next to obtuse triangles several times their rest length while
// `spokes_and_rims` stays within 0.7 strain (tests/deform/arap_test.cpp). The energy of spokes
// and rims is a sum of per-triangle Dirichlet energies, never negative; with negative weights
// the spokes energy can be.
//
// Vertices at exactly the same rest position (seams) are one unknown: the result cannot tear.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/deform/harmonic_field.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::detail {
struct ArapEdge;     // one cell term (src/deform/arap.cpp)
struct ArapRhsTerm;  // one right-hand-side term of a node (src/deform/arap.cpp)
}  // namespace cgamesh::detail

namespace cgamesh::deform {

/// The cells whose rigidity the energy measures.
enum class ArapEnergy {
  spokes,           ///< the edges at each vertex (eq. 9)
  spokes_and_rims,  ///< the edges of each triangle at the vertex (libigl's surface default)
};

/// How the local step finds each cell's rotation.
enum class ArapLocalStep {
  rotor,  ///< top eigenvector of Horn's 4×4 matrix (section VII): Newton on its characteristic quartic
  svd,    ///< polar decomposition of the 3×3 covariance (the reference)
};

struct ArapOptions {
  ArapEnergy energy = ArapEnergy::spokes_and_rims;
  /// cotangent (default) or clamped_cotangent; mean_value is refused (not an ARAP energy).
  LaplacianWeights weights = LaplacianWeights::cotangent;
  ArapLocalStep local_step = ArapLocalStep::rotor;
  int iterations = 10;   ///< at most this many local/global iterations, ≥ 1
  double tolerance = 0;  ///< stop once the energy falls by less than tolerance × its value; 0: never
  int threads = 0;       ///< local step, right-hand sides, back-substitutions (0: all hardware threads)
};

struct ArapReport;

/// Everything arap_solve() needs for one mesh and one handle set: the welded nodes, the
/// factorised Laplacian, the cells and the right-hand-side operator. Built by
/// arap_precompute(); move-only.
class ArapData {
 public:
  ArapData(ArapData&& other) noexcept;
  ArapData& operator=(ArapData&& other) noexcept;
  ArapData(const ArapData&) = delete;
  ArapData& operator=(const ArapData&) = delete;
  ~ArapData();

  /// The options it was built with (arap_solve() iterates by them).
  [[nodiscard]] const ArapOptions& options() const noexcept { return options_; }
  /// #V of the mesh.
  [[nodiscard]] Eigen::Index vertex_count() const noexcept { return system_.vertex_count(); }
  /// #N welded nodes (vertices at one rest position are one node).
  [[nodiscard]] Eigen::Index node_count() const noexcept { return rest_.rows(); }
  /// #H handles, the rows arap_solve() expects in its handle positions.
  [[nodiscard]] Eigen::Index handle_count() const noexcept { return system_.constrained_count(); }

 private:
  friend ArapData arap_precompute(const mesh::Mesh& mesh, std::span<const int> handles, const ArapOptions& options);
  friend ArapReport arap_solve(const ArapData& data, const Eigen::MatrixXd& handle_positions,
                               Eigen::MatrixXd& positions);
  ArapData();

  ArapOptions options_;
  HarmonicPrecomputation system_;  ///< welded nodes, the factorised free block of the Laplacian
  Eigen::MatrixXd rest_;           ///< #N×3 rest position of each welded node
  std::vector<int> edge_begin_;    ///< #N+1: cell n holds edges_[edge_begin_[n], edge_begin_[n+1])
  std::vector<detail::ArapEdge> edges_;
  std::vector<double> rest_energy_;  ///< #N Σ w‖p_a − p_b‖² over each cell
  std::vector<int> rhs_begin_;       ///< #N+1: node n sums rhs_[rhs_begin_[n], rhs_begin_[n+1])
  std::vector<detail::ArapRhsTerm> rhs_;
};

/// What arap_solve() did.
struct ArapReport {
  /// The energy E(p′) = min over rotations of eqs. 9–11 (the cells of options.energy): [0] of the
  /// initial guess, [k] after iteration k. Never increases.
  std::vector<double> energies;
  int iterations = 0;  ///< iterations run (fewer than options.iterations when the tolerance stopped them)
};

/// Builds the cells, the right-hand-side operator and the factorised Laplacian with the handle
/// rows substituted (eq. 12).
/// @param[in] mesh     #V rest positions and #F triangles
/// @param[in] handles  #H vertex indices whose positions arap_solve() prescribes (welded copies
///                     of a handle vertex are handles too)
/// @param[in] options  energy, weights, local step, iterations, threads
/// @throws InvalidInputError for an empty handle set, an index outside [0, #V), mean-value
///         weights, iterations < 1, a negative or non-finite tolerance, or a connected part
///         without a handle vertex (its placement would be undetermined);
///         SolverError when the factorisation fails.
[[nodiscard]] ArapData arap_precompute(const mesh::Mesh& mesh, std::span<const int> handles,
                                       const ArapOptions& options = {});

/// Deforms: iterates the local and global steps from `positions`.
/// @param[in]     data              from arap_precompute()
/// @param[in]     handle_positions  #H×3 targets, row h for handles[h]
/// @param[in,out] positions         #V×3 initial guess (e.g. the previous frame's result), or
///                                  empty: the rest positions; the handles are set to their
///                                  targets first. Out: the deformed positions, handles exact.
/// @return the energy per iteration and the iteration count
/// @throws InvalidInputError when handle_positions is not #H×3 or not finite, gives two
///         positions to one welded vertex, or positions is neither empty nor #V×3 finite;
///         SolverError when the solve fails.
ArapReport arap_solve(const ArapData& data, const Eigen::MatrixXd& handle_positions, Eigen::MatrixXd& positions);

/// The rotation R maximising tr(R S), i.e. minimising Σ w‖v′ − R v‖² for S = Σ w v v′ᵀ, as the
/// top eigenvector of Horn's 4×4 matrix P of S (section VII).
/// @param[in] covariance  S (3×3)
/// @return the unit rotor M (R v = M v M̃); the identity when S is zero
[[nodiscard]] cga::Rotor<double> arap_rotor(const Eigen::Matrix3d& covariance);

/// The same rotation by the SVD S = U Σ Vᵀ: R = V diag(1, 1, det(V Uᵀ)) Uᵀ.
[[nodiscard]] Eigen::Matrix3d arap_rotation_svd(const Eigen::Matrix3d& covariance);

}  // namespace cgamesh::deform
