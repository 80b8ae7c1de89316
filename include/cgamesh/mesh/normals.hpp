#pragma once
// Vertex normals of a reshaped mesh (a deformed rest shape) that keep the mesh's own smoothing:
// its hard edges stay hard, its UV seams stay invisible.

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::mesh {

/// Unit area-weighted vertex normals: per vertex, the normalised sum of the cross products of
/// the faces around it (zero for a vertex that no face with area touches).
/// @param[in] positions  #V×3 positions
/// @param[in] faces      #F×3 vertex indices, each in [0, #V)
/// @return #V×3 normals
[[nodiscard]] RowMatrixXf<3> area_weighted_normals(const RowMatrixXf<3>& positions, const Faces& faces);

/// Unit vertex normals of `m`'s faces at new positions. The corners at one rest position whose
/// rest normals agree (within 1°: split only for UVs or joints) form one smoothing group and
/// get one normal, the area-weighted mean of the new normals of the faces around the group; a
/// corner whose rest normal differs (a hard edge) keeps its own group. A group whose faces have
/// no area keeps its rest normal.
/// @param[in] m          the mesh at rest, with its normals (#V×3) and faces
/// @param[in] positions  #V×3 new positions of m's vertices
/// @return #V×3 unit normals; 0 rows when m has no normals (nothing to keep)
/// @throws InvalidInputError when positions does not have #V rows.
[[nodiscard]] RowMatrixXf<3> reshaped_normals(const Mesh& m, const RowMatrixXf<3>& positions);

}  // namespace cgamesh::mesh
