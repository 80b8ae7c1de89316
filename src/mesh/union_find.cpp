#include "cgamesh/mesh/union_find.hpp"

#include <algorithm>

namespace cgamesh::mesh {

UnionFind::UnionFind(std::size_t n) : parent_(n) {
  for (std::size_t a = 0; a < n; ++a) parent_[a] = static_cast<int>(a);
}

int UnionFind::find(int a) noexcept {
  while (parent_[static_cast<std::size_t>(a)] != a)
    a = parent_[static_cast<std::size_t>(a)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(a)])];
  return a;
}

void UnionFind::unite(int a, int b) noexcept {
  a = find(a);
  b = find(b);
  if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
}

}  // namespace cgamesh::mesh
