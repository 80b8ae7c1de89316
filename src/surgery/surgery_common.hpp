#pragma once
// Private to surgery: small helpers the cut, tear and drill share.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/surgery/placement.hpp"

namespace cgamesh::surgery {

using MeshFaces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Key of the undirected edge {a, b}.
[[nodiscard]] std::uint64_t edge_key(int a, int b) noexcept;
/// Key of the directed edge a -> b.
[[nodiscard]] std::uint64_t directed_key(int a, int b) noexcept;

/// Signed distance of every placed vertex from the plane n·x = d: X·Π with X = up(x) and
/// Π = n + d e∞ (cga), or n·x − d (euclidean).
[[nodiscard]] std::vector<double> signed_distances(const mesh::RowMatrixXf<3>& placed, const Eigen::Vector3d& n, double d,
                                                   const cga::Vector<double>& plane, Predicates predicates);

/// Length of the bounding-box diagonal of the rows of `points` (0 when empty).
[[nodiscard]] double bounding_diagonal(const mesh::RowMatrixXf<3>& points);

/// Welds vertices by exact position, on demand: only the vertices asked about are hashed, so a
/// local operation on a large mesh stays local. Seam copies get the same id (the first of them
/// asked about).
class PositionWelder {
 public:
  explicit PositionWelder(const mesh::RowMatrixXf<3>& positions) : positions_(positions) {}
  [[nodiscard]] int operator()(int v);

 private:
  struct Hash {
    std::size_t operator()(const std::array<float, 3>& p) const noexcept;
  };
  const mesh::RowMatrixXf<3>& positions_;
  std::unordered_map<std::array<float, 3>, int, Hash> first_;
};

/// Per vertex, the welded id of PositionWelder for the whole mesh.
[[nodiscard]] std::vector<int> weld_by_position(const mesh::RowMatrixXf<3>& positions);

/// A unit vector perpendicular to the unit vector n.
[[nodiscard]] Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n);

/// @throws InvalidInputError when `placement` does not hold one #V×3 block per mesh of `model`.
void require_placement_fits(const anim::RiggedModel& model, const Placement& placement);

}  // namespace cgamesh::surgery
