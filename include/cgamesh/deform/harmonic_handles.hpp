#pragma once
// Motor handles by harmonic coordinates (paper section IV): n handle vertex sets H_j, one
// harmonic field lambda_j per handle (1 on H_j, 0 on every other handle), and per vertex the
// motor M_i = exp(sum_j lambda_j(p_i) log R_j), bound and deformed as in eq. (2)
// (deform/motor_blend.hpp). The fields sum to 1 at every vertex (the boundary values do, and
// the solve is linear) and, with mean-value weights, lie in [0, 1].

#include <span>
#include <vector>

#include "cgamesh/deform/harmonic_field.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

/// Harmonic coordinates of every vertex with respect to the handles (section IV).
/// @param[in] mesh     #V rest positions, #F faces
/// @param[in] handles  #n disjoint, non-empty vertex index sets
/// @return #V x n coordinates lambda_j(p_i), column j is 1 on handle j and 0 on the others
/// @throws InvalidInputError when there is no handle, a handle is empty, two handles share a
///         vertex (or a welded position), an index is out of range, or a part of the mesh has no
///         handle; SolverError as harmonic_precompute().
[[nodiscard]] Eigen::MatrixXd harmonic_coordinates(const mesh::Mesh& mesh, std::span<const std::vector<int>> handles,
                                                   const HarmonicOptions& options = {});

/// Binds the mesh to one key versor per handle (harmonic_coordinates + MotorBlend).
/// @param[in] rest_keys  #n versors R_j at rest, in the order of `handles`
/// @throws as harmonic_coordinates() and MotorBlend.
[[nodiscard]] MotorBlend bind_harmonic_handles(const mesh::Mesh& mesh, std::span<const std::vector<int>> handles,
                                               std::span<const cga::Versor<double>> rest_keys,
                                               const HarmonicOptions& options = {},
                                               const MotorBlendOptions& blend_options = {});

}  // namespace cgamesh::deform
