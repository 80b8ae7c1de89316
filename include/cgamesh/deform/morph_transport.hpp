#pragma once
// Morph targets carried through a deformation of the rest shape. A target's displacements are
// relative to the surface (a smile on a face): where a deformation bends, turns or stretches the
// surface, the displacements must bend, turn and stretch with it, or the shape they make is
// pasted on in the wrong direction.

#include <vector>

#include <Eigen/Core>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

/// The local linear map of a reshaping at each vertex: the 3×3 J minimising Σ |J e − e′|² over
/// the edges e from the vertex to the other corners of the faces around it (rest → moved),
/// and its unit normal scaled by the square root of the area of those faces, mapped to the moved
/// normal scaled alike (so that J is defined off the surface too: displacements along the
/// normal stay along it, as a swelling of skin does, and grow as the area does). Vertices at one position (seams) share one map,
/// fitted on all their faces. Exact for a similarity (rotation, translation, uniform scale);
/// the identity where the faces around a vertex have no area.
/// @param[in] rest   #V×3 rest positions
/// @param[in] moved  #V×3 the same vertices reshaped
/// @param[in] faces  #F×3 vertex indices, each in [0, #V)
/// @return #V maps
/// @throws InvalidInputError when rest and moved differ in size.
[[nodiscard]] std::vector<Eigen::Matrix3d> local_linear_maps(const mesh::RowMatrixXf<3>& rest,
                                                             const mesh::RowMatrixXf<3>& moved,
                                                             const mesh::Faces& faces);

/// Carries `m`'s morph targets from its rest shape to the reshaped one: each position
/// displacement Δ of vertex v becomes J_v Δ and each normal displacement the rotation of J_v
/// (its polar factor) applied to it, J_v = local_linear_maps(m.positions, moved, m.faces)[v].
/// The positions of `m` are not changed (the caller sets them to `moved`).
/// @param[in,out] m      the mesh at rest, with its targets
/// @param[in]     moved  #V×3 its new rest positions
/// @throws InvalidInputError when moved does not have #V rows.
void transport_morph_targets(mesh::Mesh& m, const mesh::RowMatrixXf<3>& moved);

}  // namespace cgamesh::deform
