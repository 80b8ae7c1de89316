#pragma once
// Welding by position: vertices split at seams (for UVs, normals or joints) are one point of
// the surface. The one rule every part of cgamesh welds by: bit-identical float positions,
// with −0 equal to +0.

#include <span>
#include <vector>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::mesh {

/// Per vertex, the smallest index of the vertices at exactly its position.
/// @param[in] positions  #V×3 positions
/// @return #V representative ids (id[v] ≤ v, id[id[v]] = id[v])
[[nodiscard]] std::vector<int> weld_by_position(const RowMatrixXf<3>& positions);

/// Numbers the classes of a welding densely, in the order of their first vertex.
/// @param[in,out] ids  #V representative ids (as weld_by_position gives), replaced by class
///                     numbers 0 … count−1
/// @return count, the number of classes
/// @throws InvalidInputError when ids[v] is not in [0, v].
int number_classes(std::span<int> ids);

}  // namespace cgamesh::mesh
