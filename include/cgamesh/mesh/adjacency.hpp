#pragma once
// Face adjacency across welded edges: the one rule that the surface index, the in-place
// surgery and every walk over a mesh share.

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/mesh/row_array.hpp"

namespace cgamesh::mesh {

/// Per face f and edge k (corner k to corner k + 1), the face across it, or −1.
using FaceNeighbors = std::vector<std::array<int, 3>>;

/// Face adjacency over welded ids: two face edges are twins when they are the only two on one
/// welded edge and run in opposite directions (a consistently oriented manifold edge). Boundary,
/// non-manifold, inconsistently oriented and degenerate (welded ends equal) edges get −1.
/// @param[in] faces  #F×3 vertex ids
/// @param[in] weld   #V welded id of each vertex (weld_by_position), or any labelling
/// @return #F neighbour triples
/// @throws InvalidInputError for a face vertex outside [0, #weld).
[[nodiscard]] FaceNeighbors face_adjacency(const Faces& faces, std::span<const int> weld);

/// The same rule, for some face edges only (an edit in place): links each edge of `edges` to its
/// twin among `edges`. The caller names every face edge that lies on the welded edges concerned
/// (the new faces' edges and the old edges they border), as the twin is looked for among them.
/// @param[in]     faces     #F×3 vertex ids
/// @param[in]     weld      #V welded ids
/// @param[in]     edges     (face, k) pairs
/// @param[in,out] neighbor  #F triples; the entries of `edges` are set
void link_twins(const Faces& faces, std::span<const int> weld, std::span<const std::array<int, 2>> edges,
                FaceNeighbors& neighbor);

/// The edge of face neighbor[f][k] that lies across edge k of f, or −1 when there is none.
[[nodiscard]] int edge_across(const FaceNeighbors& neighbor, int f, int k) noexcept;

}  // namespace cgamesh::mesh
