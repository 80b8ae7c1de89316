#pragma once
// Morph targets (blend shapes) at a pose: the weights a pose gives a mesh, and the rest mesh they
// make, which skinning then poses (glTF's order: morph, then skin).

#include <span>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::anim {

/// The weights of `mesh`'s morph targets in `pose`: what a clip gives the mesh's node
/// (Pose::morph_weights) when it gives as many as the mesh has targets, else the mesh's defaults
/// (Mesh::morph_weights). Empty for a mesh without targets.
[[nodiscard]] std::span<const float> morph_weights(const Pose& pose, const mesh::Mesh& mesh) noexcept;

/// Sets weight `target` (0 <= target < #targets) of `mesh`'s morph targets to `weight` in `pose`:
/// the pose then gives the mesh's node what morph_weights(pose, mesh) gave with this one weight
/// changed (a user's slider over a clip's or the file's weights). Meshes on one node share the
/// weights, as the primitives of a glTF mesh do.
/// @throws InvalidInputError when the mesh has no such target or no node (-1) to hold weights in
///         a pose, or `weight` is NaN or infinite.
void set_morph_weight(Pose& pose, const mesh::Mesh& mesh, std::size_t target, float weight);

/// A morph weight set by its target's name over what a clip or the file gives (a viewer's
/// slider, the CLI's --morph NAME=W).
struct MorphSetting {
  std::string target;
  float weight = 0;
};

/// Sets every morph target named `name`, on any mesh of `meshes`, to `weight` in `pose` (as the
/// overload above).
/// @throws InvalidInputError naming `name` and the targets there are when no mesh has one so named.
void set_morph_weight(Pose& pose, std::span<const mesh::Mesh> meshes, std::string_view name, float weight);

/// True when some weight is non-zero: the mesh then differs from its rest mesh.
[[nodiscard]] bool morphs(std::span<const float> weights) noexcept;

/// The displacement Σ wₖ Δₖ(v) of vertex v (0 <= v < #V) at `weights` (#targets).
[[nodiscard]] Eigen::Vector3f morph_offset(const mesh::Mesh& mesh, std::span<const float> weights, Eigen::Index v);

/// Rows [begin, end) of `mesh`'s rest positions and normals with its morph targets applied at
/// `weights` (what skinning then poses): positions rest + Σ wₖ Δₖ, normals n + Σ wₖ Δnₖ
/// renormalised (a zero sum keeps n), as three.js and the glTF specification do. Only the rows
/// asked for are made, so a skinning job morphs its own vertices and nothing else.
/// @param[in] weights  #targets weights
/// @param[in] begin, end  vertex range, 0 <= begin <= end <= #V
/// @param[out] positions  (end-begin)×3, row r for vertex begin + r
/// @param[out] normals  (end-begin)×3 likewise; null, or a mesh without normals: not made
/// @throws InvalidInputError as check_morph_weights(), or for a range outside the mesh.
void morph_rows(const mesh::Mesh& mesh, std::span<const float> weights, Eigen::Index begin, Eigen::Index end,
                mesh::RowMatrixXf<3>& positions, mesh::RowMatrixXf<3>* normals);

/// @throws InvalidInputError (naming the mesh) when `weights` is neither empty nor one finite
///         weight per morph target of `mesh`, or a target does not have a row per vertex.
void check_morph_weights(const mesh::Mesh& mesh, std::span<const float> weights);

}  // namespace cgamesh::anim
