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

/// Joins the vertices of `m` that agree in position and in every attribute (normal, UV, joints
/// and weights, generated flag), bit for bit (−0 = +0): seams, where an attribute differs,
/// stay split; the rest is shared (file formats and importers that give one vertex per face
/// corner make triangle soups). The first vertex of each class keeps its place in the order,
/// and its file_index (which is not compared: a soup's corners each have their own).
/// @param[in,out] m  the mesh; faces renumbered
/// @return the number of vertices removed
int join_identical_vertices(Mesh& m);

}  // namespace cgamesh::mesh
