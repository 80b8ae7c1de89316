#pragma once
// Private to the library: welding on demand, for local operations on large meshes.

#include <array>
#include <cstddef>

#include "cgamesh/mesh/mesh.hpp"

#include "../flat_map.hpp"

namespace cgamesh::mesh {

/// Row v of `positions` as a key of its exact position: +0.0f folds -0.0f into 0.0f, whose bits
/// differ.
[[nodiscard]] inline std::array<float, 3> position_key(const RowMatrixXf<3>& positions, Eigen::Index v) {
  return {positions(v, 0) + 0.0f, positions(v, 1) + 0.0f, positions(v, 2) + 0.0f};
}

/// Hash of a position by its bits.
struct PositionHash {
  std::size_t operator()(const std::array<float, 3>& p) const noexcept;
};

/// Welds vertices by exact position (weld.hpp's rule), on demand: only the vertices asked about
/// are hashed, so a local operation on a large mesh stays local. Seam copies get the same id:
/// the first of them asked about (the smallest, when asked in increasing order).
class PositionWelder {
 public:
  explicit PositionWelder(const RowMatrixXf<3>& positions) : positions_(positions) {}
  [[nodiscard]] int operator()(int v);

 private:
  const RowMatrixXf<3>& positions_;
  FlatMap<int, std::array<float, 3>, PositionHash> first_;
};

}  // namespace cgamesh::mesh
