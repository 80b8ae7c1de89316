#pragma once
// The connected pieces of a mesh: what a cut or a through-drill leaves apart. Vertices at the
// same rest position (seam copies, split for UVs, normals or joints) count as one point, so a
// textured model is one piece until a tool separates it.

#include <span>
#include <vector>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::surgery {

struct Pieces {
  std::vector<int> of_vertex;  ///< #V piece of each vertex, 0 … count−1, numbered by first face
  int count = 0;               ///< number of pieces (vertices in no face form no piece: −1)
};

/// The pieces of `mesh`: faces joined through shared vertices, welded by exact rest position.
/// O(V + F) expected.
/// @throws InvalidInputError for a face index out of range.
[[nodiscard]] Pieces pieces(const mesh::Mesh& mesh);

/// The same with the welding given: `weld` holds, per vertex, the id of the vertex it counts as
/// (e.g. MeshIndex::weld of a LiveModel, where the copies a cut or a tear separated stay apart
/// although they share a rest position).
/// @throws InvalidInputError for a face index out of range, or weld ids that do not fit.
[[nodiscard]] Pieces pieces(const mesh::Mesh& mesh, std::span<const int> weld);

}  // namespace cgamesh::surgery
