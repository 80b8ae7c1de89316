#pragma once
// Cage deformation by harmonic coordinates (paper section VI; Joshi et al., "Harmonic coordinates
// for character articulation", 2007). A closed triangle cage encloses the mesh; each mesh vertex
// p̂ gets one coordinate λⱼ per cage vertex, the values at p̂ of the harmonic functions that are
// piecewise linear (barycentric) on the cage faces and 1 at cage vertex j. They are ≥ 0, sum to 1
// and reproduce affine maps of the cage. A frame then moves the vertices by
//  - classic cage deformation: posed cage vertices cⱼ, p = p̂ + Σ λⱼ (cⱼ − ĉⱼ) — the paper's
//    p = Σ λⱼ cⱼ written as a displacement, so that the rest cage is the identity exactly and not
//    only up to the coordinates' grid error;
//  - motor cage: a motor Rⱼ per cage vertex, M = exp(Σ λⱼ log Rⱼ), p = M p̂ M̃ (bound as section
//    III.A does: identity motors leave the mesh unchanged, one motor R for all moves it by R).
//
// The coordinates are solved on a grid (Joshi et al. section 3.1): the cage's bounding box cut
// into cubic cells, `resolution` on its longest side; nodes inside the cage (winding number ≥ ½)
// are unknowns of the 7-point Laplacian, nodes outside but within √3 cells of the cage hold the
// barycentric value of their closest cage point. Every 6-neighbour of an inside node and every
// corner of a cell holding an inside point is such a node, so trilinear interpolation at a mesh
// vertex reads solved or boundary values only. Linear functions are discrete-harmonic and the
// boundary values are off by at most √3 h (h the cell size) from them, so by the discrete
// maximum principle Σ λⱼ ĉⱼ reproduces p̂ within √3 h per coordinate.

#include <array>
#include <filesystem>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

/// A closed triangle cage: its vertices and faces (each row 3 vertex indices).
struct Cage {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertices;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces;
};

/// Reads a cage from a Wavefront OBJ: `v x y z` and `f a b c ...` lines (indices 1-based or
/// negative, `a/t/n` forms accepted, polygons fanned into triangles); other lines are ignored.
/// Vertex j of the cage is the file's j-th `v` line, so spec handles index it as written.
/// @param[in] path  the OBJ file
/// @throws FileError when it cannot be read or a `v` or `f` line is malformed (naming the line).
[[nodiscard]] Cage read_cage_obj(const std::filesystem::path& path);

/// The box [lo, hi] as a cage: each side cut into cuts[b] × cuts[c] squares (b, c its axes), two
/// outward triangles each — the simplest cage around a mesh's bounding box.
/// @param[in] lo, hi  corners, finite, lo < hi on every axis
/// @param[in] cuts    segments per axis, each ≥ 1
/// @throws InvalidInputError otherwise.
[[nodiscard]] Cage box_cage(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const std::array<int, 3>& cuts);

/// Checks that `cage` is a closed, edge-manifold, consistently oriented triangle mesh: every edge
/// is used by exactly two faces, once in each direction.
/// @throws InvalidInputError for fewer than 4 vertices or faces, a non-finite vertex or a face
///         index out of range; TopologyError naming the first degenerate face (a repeated vertex),
///         boundary edge (open cage), edge of more than two faces (non-manifold) or edge used twice
///         in one direction (inconsistent orientation).
void check_cage(const Cage& cage);

struct CageOptions {
  int resolution =
      64;  ///< grid cells on the longest side of the cage's box, in [kMinCageResolution, kMaxCageResolution]
  /// The Laplace solves stop when every cage vertex's residual is below tolerance × its right-hand
  /// side (ℓ2); 1e-6 leaves a solver error far below the grid error.
  double tolerance = 1e-6;
  int threads = 0;  ///< threads of the precompute and of each frame; 0: all hardware threads
  /// #V how messages number the vertices of `rest` (e.g. Mesh::file_index; a negative entry:
  /// the row), or empty: by row.
  std::span<const int> vertex_labels;
};

inline constexpr int kMinCageResolution = 4;
/// 256³ nodes of 8 bytes per cage vertex and solver vector: beyond, memory rather than time limits.
inline constexpr int kMaxCageResolution = 256;

/// Harmonic coordinates of `rest` in `cage` (Joshi et al. 2007, paper section VI): the grid
/// Laplacian is assembled once and solved for all cage vertices — conjugate gradients, matrix-free
/// over the grid's 7-point stencil, 8 cage vertices in lockstep per thread, preconditioned by a
/// multigrid V-cycle over the grids of halving resolution (about 16 iterations at 64³, whatever
/// the resolution; a sparse factorisation of a 64³ grid would not fit the time, Eigen's
/// SimplicialLDLT takes 30 s at 32³ here) — then interpolated trilinearly at the mesh vertices and
/// renormalised to sum 1.
/// @param[in] rest     #V×3 mesh positions, each inside the cage
/// @param[in] cage     a cage that passes check_cage()
/// @param[in] options  resolution, tolerance and threads
/// @return #V×#C coordinates λ, row i for vertex i, each ≥ 0 and summing to 1
/// @throws as check_cage(); InvalidInputError naming the first vertex outside the cage (winding
///         number < ½), or for a resolution out of range or a tolerance not in (0, 1);
///         SolverError when the solves do not converge.
[[nodiscard]] Eigen::MatrixXd cage_coordinates(const mesh::RowMatrixXf<3>& rest, const Cage& cage,
                                               const CageOptions& options = {});

/// Writes coordinates as a NumPy .npy file (format 1.0, little-endian float64, C order, shape
/// #V×#C), readable by numpy.load.
/// @throws WriteError when the file cannot be written.
void save_cage_coordinates(const std::filesystem::path& path, const Eigen::MatrixXd& coordinates);

/// Reads coordinates written by save_cage_coordinates() (or numpy.save of a float64 #V×#C array).
/// @param[in] path      the .npy file
/// @param[in] vertices  #V expected
/// @param[in] cage      #C expected
/// @throws FileError when it cannot be read, is not a float64 C-order 2-D .npy file, is truncated,
///         has another shape than #V×#C (naming both), or rows that are not coordinates (a value
///         not finite or below −1e-9, a row sum off 1 by more than 1e-6).
[[nodiscard]] Eigen::MatrixXd load_cage_coordinates(const std::filesystem::path& path, Eigen::Index vertices,
                                                    Eigen::Index cage);

/// How many coordinates a vertex keeps for its frames.
struct CageSparsity {
  /// The largest coordinates kept per vertex, ≥ 1; the kept ones are renormalised to sum 1, so a
  /// rigid cage motion (or one motor) still moves the mesh rigidly.
  int max_weights = 16;
  double min_weight = 1e-4;  ///< coordinates below are dropped (before renormalising), in [0, 1)
};

class CageDeformation {
 public:
  /// Keeps, per vertex, the coordinates `sparsity` selects.
  /// @param[in] rest         #V×3 rest positions p̂
  /// @param[in] cage         the rest cage ĉ (#C vertices)
  /// @param[in] coordinates  #V×#C, e.g. from cage_coordinates()
  /// @throws InvalidInputError when the sizes disagree, a coordinate is not finite, or the
  ///         sparsity is out of range.
  CageDeformation(const mesh::RowMatrixXf<3>& rest, const Cage& cage, const Eigen::MatrixXd& coordinates,
                  const CageSparsity& sparsity = {}, int threads = 0);

  [[nodiscard]] Eigen::Index vertex_count() const noexcept { return rest_.rows(); }
  [[nodiscard]] Eigen::Index cage_vertex_count() const noexcept { return cage_.rows(); }
  /// The rest cage vertices ĉ.
  [[nodiscard]] const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& cage_vertices() const noexcept {
    return cage_;
  }
  /// The kept coordinates of vertex i: (cage vertex, λ), renormalised to sum 1.
  [[nodiscard]] std::vector<std::pair<int, double>> weights(Eigen::Index i) const;
  /// Mean kept coordinates per vertex.
  [[nodiscard]] double mean_weights() const noexcept;

  /// Classic cage deformation: p = p̂ + Σ λⱼ (cⱼ − ĉⱼ).
  /// @param[in]  points  #C posed cage vertices c
  /// @param[out] out     #V×3 (resized)
  /// @throws InvalidInputError when points has the wrong size.
  void deform_points(std::span<const Eigen::Vector3d> points, mesh::RowMatrixXf<3>& out) const;

  /// Motor cage (section VI): p = M p̂ M̃ with M = exp(Σ λⱼ log Rⱼ).
  /// @param[in]  motors  #C cage vertex versors R (TRS similarities); identities are the rest cage
  /// @param[out] out     #V×3 (resized)
  /// @throws InvalidInputError when motors has the wrong size or a motor is not a similarity.
  void deform_motors(std::span<const cga::Versor<double>> motors, mesh::RowMatrixXf<3>& out) const;

 private:
  /// One frame: `out` sized, then job(begin, end) over the threads.
  template <class Job>
  void frame(std::size_t count, const char* what, mesh::RowMatrixXf<3>& out, Job&& job) const;
  /// Σ λⱼ table.col(j) over the kept coordinates of vertex i.
  template <int N>
  [[nodiscard]] Eigen::Matrix<float, N, 1> contract(
      Eigen::Index i, const Eigen::Matrix<float, N, Eigen::Dynamic>& table) const noexcept;

  mesh::RowMatrixXf<3> rest_;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> cage_;
  std::vector<int> offset_;  ///< #V + 1: vertex i's coordinates are [offset_[i], offset_[i + 1])
  std::vector<int> index_;   ///< cage vertex of each kept coordinate
  std::vector<float> weight_;
  int threads_;
};

}  // namespace cgamesh::deform
