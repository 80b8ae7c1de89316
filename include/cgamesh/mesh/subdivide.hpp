#pragma once
// 1 -> 4 midpoint subdivision of a skinned mesh.

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::mesh {

/// Splits every triangle into four at its edge midpoints. A new vertex takes the mean of its
/// edge's endpoints for position, normal (renormalised) and UV, and their blended skin
/// weights: the mean weight per joint, the 4 largest kept and renormalised (paper section 4.3,
/// new vertices on an edge). Seams stay split: an edge is shared only through shared vertex
/// indices, so the two sides of a seam get their own midpoints. Faces 4f … 4f + 3 keep face
/// f's material.
/// @param[in] in  mesh with #V vertices and #F faces
/// @return mesh with #V + #E vertices and 4 #F faces (the first #V vertices unchanged)
[[nodiscard]] Mesh subdivide_midpoint(const Mesh& in);

}  // namespace cgamesh::mesh
