#include "cgamesh/mesh/adjacency.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "cgamesh/errors.hpp"

#include "../flat_map.hpp"

namespace cgamesh::mesh {

void link_twins(const Faces& faces, std::span<const int> weld, std::span<const std::array<int, 2>> edges,
                FaceNeighbors& neighbor) {
  // Grouped by undirected welded edge, a manifold edge is a group of two, one each way.
  struct Edge {
    std::uint64_t key;
    bool forward;  ///< welded ids increase along the face's edge
  };
  std::vector<Edge> keyed(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [f, k] = edges[e];
    const int a = weld[static_cast<std::size_t>(faces(f, k))],
              b = weld[static_cast<std::size_t>(faces(f, (k + 1) % 3))];
    const auto lo = static_cast<std::uint32_t>(std::min(a, b)), hi = static_cast<std::uint32_t>(std::max(a, b));
    // Degenerate edges get a key of their own, which no other edge has: a group of one.
    keyed[e] = {a == b ? ~std::uint64_t{0} - e : (std::uint64_t{lo} << 32) | hi, a < b};
  }
  // Per edge: the first edge of its group; per first edge: the group's size and second edge.
  FlatMap<int> first_of;
  first_of.reserve(edges.size());
  std::vector<int> first(edges.size()), size(edges.size(), 0), second(edges.size(), -1);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto g = static_cast<std::size_t>(*first_of.try_emplace(keyed[e].key, static_cast<int>(e)).first);
    first[e] = static_cast<int>(g);
    if (size[g]++ == 1) second[g] = static_cast<int>(e);
  }
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto g = static_cast<std::size_t>(first[e]);
    const auto twin = static_cast<std::size_t>(e == g ? second[g] : static_cast<int>(g));
    const bool manifold = size[g] == 2 && keyed[e].forward != keyed[twin].forward;
    neighbor[static_cast<std::size_t>(edges[e][0])][static_cast<std::size_t>(edges[e][1])] =
        manifold ? edges[twin][0] : -1;
  }
}

FaceNeighbors face_adjacency(const Faces& faces, std::span<const int> weld) {
  const auto nv = static_cast<long>(weld.size());
  std::vector<std::array<int, 2>> edges;
  edges.reserve(static_cast<std::size_t>(3 * faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      if (faces(f, k) < 0 || faces(f, k) >= nv)
        throw InvalidInputError("face adjacency: face " + std::to_string(f) + " names vertex " +
                                std::to_string(faces(f, k)) + " outside [0, " + std::to_string(nv) + ")");
      edges.push_back({static_cast<int>(f), k});
    }
  FaceNeighbors neighbor(static_cast<std::size_t>(faces.rows()), {-1, -1, -1});
  link_twins(faces, weld, edges, neighbor);
  return neighbor;
}

int edge_across(const FaceNeighbors& neighbor, int f, int k) noexcept {
  const int g = neighbor[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
  if (g < 0) return -1;
  for (int j = 0; j < 3; ++j)
    if (neighbor[static_cast<std::size_t>(g)][static_cast<std::size_t>(j)] == f) return j;
  return -1;
}

}  // namespace cgamesh::mesh
