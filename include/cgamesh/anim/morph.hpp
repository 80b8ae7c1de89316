#pragma once
// Morph targets (blend shapes) at a pose: the weights a pose gives a mesh, and the rest mesh they
// make, which skinning then poses (glTF's order: morph, then skin).

#include <span>

#include <Eigen/Core>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::anim {

/// The weights of `mesh`'s morph targets in `pose`: what a clip gives the mesh's node
/// (Pose::morph_weights) when it gives as many as the mesh has targets, else the mesh's defaults
/// (Mesh::morph_weights). Empty for a mesh without targets.
[[nodiscard]] std::span<const float> morph_weights(const Pose& pose, const mesh::Mesh& mesh) noexcept;

/// True when some weight is non-zero: the mesh then differs from its rest mesh.
[[nodiscard]] bool morphs(std::span<const float> weights) noexcept;

/// The displacement Σ wₖ Δₖ(v) of vertex v (0 <= v < #V) at `weights` (#targets).
[[nodiscard]] Eigen::Vector3f morph_offset(const mesh::Mesh& mesh, std::span<const float> weights, Eigen::Index v);

/// `mesh` with its morph targets applied at `weights`: positions rest + Σ wₖ Δₖ, normals
/// n + Σ wₖ Δnₖ renormalised (a zero sum keeps n), as three.js and the glTF specification do;
/// the targets themselves are dropped (the result is what skinning poses).
/// @param[in] weights  #targets weights
/// @throws InvalidInputError as check_morph_weights().
[[nodiscard]] mesh::Mesh morphed(const mesh::Mesh& mesh, std::span<const float> weights);

/// @throws InvalidInputError (naming the mesh) when `weights` is neither empty nor one finite
///         weight per morph target of `mesh`, or a target does not have a row per vertex.
void check_morph_weights(const mesh::Mesh& mesh, std::span<const float> weights);

}  // namespace cgamesh::anim
