#pragma once
// Free-form deformation (paper section V): a lattice of l×m×n control points over a box, and
// per vertex the tensor-product weights w_{u,v,k} = B_u(λ1) B_v(λ2) B_k(λ3) of its lattice
// coordinates (eq. 8), computed once at bind. A frame then moves the vertices by
//  - classic FFD (Sederberg–Parry, eq. 6): displaced control points, p = p̂ + Σ w (P − P̂) —
//    eq. 6 itself for a basis that reproduces the rest lattice, and the identity at rest for any;
//  - motor FFD (eqs. 7–8): a motor per control point, M = exp(Σ w log R), p = M p̂ M̃. The rest
//    motors are identities, so binding as section III.A does gives p̂ = p and identity motors
//    leave the mesh unchanged; motors that all equal R move it by R exactly.
//
// The weights are stored as their per-axis factors (the nonzero basis values of each axis), so
// memory stays O(#V (l + m + n)) and a frame contracts only the nonzero control points, in single
// precision (as the positions are stored).

#include <array>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

enum class LatticeBasis {
  bernstein,  ///< Bézier: degree l − 1 along an axis of l points (Sederberg–Parry, eq. 6); global
  bspline,    ///< uniform cubic B-spline over the points (Blender's lattice default); local
};

/// The most control points a lattice takes along an axis (Bernstein polynomials of higher degree
/// are ill-conditioned, and l m n of them weigh on every vertex).
inline constexpr int kMaxLatticeResolution = 64;

/// How the uniform cubic B-spline treats the missing neighbours of the end control points.
enum class BsplineEnds {
  linear,  ///< P₋₁ = 2P₀ − P₁: the lattice reproduces affine maps, so a rigid lattice is rigid
  repeat,  ///< P₋₁ = P₀, as Blender's lattice does: a rigid rotation bends the mesh near the faces
};

/// An oriented box: lattice coordinates t ∈ [0, 1]³ are at origin + rotation (t ∘ size).
struct LatticeBox {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();          ///< each > 0
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< a rotation matrix
};

struct Lattice {
  std::array<int, 3> resolution{2, 2, 2};  ///< l, m, n: control points per axis, in [2, kMaxLatticeResolution]
  LatticeBasis basis = LatticeBasis::bernstein;
  BsplineEnds ends = BsplineEnds::linear;  ///< bspline only
  LatticeBox box;

  /// l m n.
  [[nodiscard]] int count() const noexcept { return resolution[0] * resolution[1] * resolution[2]; }
  /// Index of control point [u, v, k] (u fastest), as FreeFormDeformation takes them.
  [[nodiscard]] int index(int u, int v, int k) const noexcept { return u + resolution[0] * (v + resolution[1] * k); }
  /// #l m n rest control points P̂, in index() order.
  [[nodiscard]] std::vector<Eigen::Vector3d> control_points() const;
};

/// The axis-aligned bounding box of `positions` grown on every side by `margin` × its diagonal.
/// @param[in] positions  #V×3, #V ≥ 1
/// @param[in] margin     ≥ 0
/// @throws InvalidInputError for no vertex, a negative or non-finite margin, or a box that is
///         flat along an axis (every vertex on one plane and margin 0, or a single point).
[[nodiscard]] LatticeBox bounding_lattice_box(const mesh::RowMatrixXf<3>& positions, double margin);

/// FreeFormDeformation's frame values: per control point N floats (displacements, generators),
/// each component's row contiguous over the control points so that a window's u-run is one load.
template <int N>
using FfdTable = Eigen::Matrix<float, N, Eigen::Dynamic, Eigen::RowMajor>;

struct FfdOptions {
  int threads = 0;  ///< threads of a frame; 0: all hardware threads
};

class FreeFormDeformation {
 public:
  /// Binds `rest` to the lattice: each vertex's lattice coordinates and nonzero basis values
  /// (eq. 8). Vertices outside the box get no weight and stay in place (Sederberg–Parry).
  /// @param[in] rest     #V×3 rest positions p̂
  /// @param[in] lattice  the lattice; its box is the rest lattice
  /// @param[in] options  threads of the bind and of each frame
  /// @throws InvalidInputError for a resolution below 2 or above kMaxLatticeResolution on an axis, a size that is not
  ///         finite and > 0, or a rotation that is not orthonormal.
  FreeFormDeformation(const mesh::RowMatrixXf<3>& rest, const Lattice& lattice, const FfdOptions& options = {});

  [[nodiscard]] Eigen::Index vertex_count() const noexcept { return rest_.rows(); }
  [[nodiscard]] const Lattice& lattice() const noexcept { return lattice_; }
  /// Vertices outside the box (not deformed), ascending.
  [[nodiscard]] const std::vector<int>& outside() const noexcept { return outside_; }
  /// The nonzero weights of vertex i: (control point index, w_{u,v,k}), eq. 8; they sum to 1.
  [[nodiscard]] std::vector<std::pair<int, double>> weights(Eigen::Index i) const;

  /// Classic FFD (eq. 6): p = p̂ + Σ w (P − P̂).
  /// @param[in]  points  #l m n posed control points P, in Lattice::index() order
  /// @param[out] out     #V×3 (resized)
  /// @throws InvalidInputError when points has the wrong size.
  void deform_points(std::span<const Eigen::Vector3d> points, mesh::RowMatrixXf<3>& out) const;

  /// Motor FFD (eqs. 7–8): p = M p̂ M̃ with M = exp(Σ w log R).
  /// @param[in]  motors  #l m n control point versors R (TRS similarities), in index() order;
  ///                     the identity is the rest lattice
  /// @param[out] out     #V×3 (resized)
  /// @throws InvalidInputError when motors has the wrong size or a motor is not a similarity.
  void deform_motors(std::span<const cga::Versor<double>> motors, mesh::RowMatrixXf<3>& out) const;

 private:
  /// One frame: `out` sized, then job(begin, end) over the threads.
  /// @throws InvalidInputError when `count` (of `what`) is not the lattice's.
  template <class Job>
  void frame(std::size_t count, const char* what, mesh::RowMatrixXf<3>& out, Job&& job) const;
  /// Σ_{u,v,k} w_{u,v,k} table.col(index(u,v,k)) for vertex i (inside the box).
  template <int N>
  [[nodiscard]] Eigen::Matrix<float, N, 1> contract(Eigen::Index i, const FfdTable<N>& table) const noexcept;

  Lattice lattice_;
  mesh::RowMatrixXf<3> rest_;
  std::array<int, 3> width_{};  ///< nonzero basis values per axis: l for Bernstein, ≤ 4 for B-splines
  /// #V×3 first control point index of each axis's window; −1 in column 0 outside the box.
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> first_;
  /// #V × (width₀ + width₁ + width₂) the per-axis basis values, axis 0 first; single precision
  /// (7 digits, as the positions) halves what a frame reads.
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> basis_;
  std::vector<int> outside_;
  int threads_;
};

}  // namespace cgamesh::deform
