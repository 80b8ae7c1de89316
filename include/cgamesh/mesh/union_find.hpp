#pragma once
// Disjoint sets of 0 … n−1: connected parts of meshes (pieces, tears, harmonic fields) and
// of polygons.

#include <cstddef>
#include <vector>

namespace cgamesh::mesh {

/// Disjoint sets of 0 … n−1 (union by index, path halving): the root of a set is its smallest
/// element, so results do not depend on the order of the unions.
class UnionFind {
 public:
  explicit UnionFind(std::size_t n);
  /// The smallest element of the set holding a.
  [[nodiscard]] int find(int a) noexcept;
  /// Joins the sets of a and b.
  void unite(int a, int b) noexcept;
  [[nodiscard]] std::size_t size() const noexcept { return parent_.size(); }

 private:
  std::vector<int> parent_;
};

}  // namespace cgamesh::mesh
