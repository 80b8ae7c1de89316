#pragma once
// New meshes whose vertices are convex combinations of an old mesh's vertices: the midpoints
// of a subdivision, the edge and face points of a cut, tear or drill (paper section 4.3).

#include <array>
#include <cstdint>
#include <span>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::mesh {

/// Where a vertex of a new mesh comes from: a copy of one old vertex, a point on an old edge,
/// or a point inside an old face, with its barycentric weights.
struct VertexSource {
  std::array<int, 3> vertex{-1, -1, -1};  ///< old vertex indices; unused slots -1
  std::array<float, 3> weight{0, 0, 0};   ///< barycentric weights of the used slots, sum 1
  /// Which used slots lend their skin influences (bit k: slot k). All by default; a cut may
  /// restrict a new vertex to the influences of its own side.
  std::uint8_t influence_mask = 0b111;

  [[nodiscard]] static VertexSource copy(int v) noexcept { return {{v, -1, -1}, {1, 0, 0}}; }
  /// The point (1 - t) a + t b.
  [[nodiscard]] static VertexSource edge(int a, int b, float t) noexcept { return {{a, b, -1}, {1 - t, t, 0}}; }
  /// The point p a + q b + r c.
  [[nodiscard]] static VertexSource face(int a, int b, int c, float p, float q, float r) noexcept {
    return {{a, b, c}, {p, q, r}};
  }
  /// 1 for a copy, 2 for an edge point, 3 for a face point.
  [[nodiscard]] int count() const noexcept { return vertex[2] >= 0 ? 3 : vertex[1] >= 0 ? 2 : 1; }
};

/// The influences of a blended vertex (paper section 4.3, "weight via barycentric
/// coordinates"): the weighted sum of the sources' weights per joint; the 4 largest kept and
/// renormalised to sum 1, sorted by decreasing weight.
/// @param[in]  skin    the old mesh's skin (non-empty)
/// @param[in]  source  the vertex's sources; slots outside influence_mask are ignored (all, when
///                     the mask leaves no positive weight)
/// @param[out] joints, weights  the new vertex's 4 palette indices and weights
void blend_influences(const Skin& skin, const VertexSource& source, std::span<std::uint16_t, 4> joints,
                      std::span<float, 4> weights) noexcept;

/// A mesh whose vertices are blends of `old`'s: positions, normals (renormalised), UVs, morph
/// displacements and skin influences; palette, inverse binds, morph target names and default
/// weights, name, node and material copied (not face_materials:
/// the new faces' origins are the caller's to know).
/// @param[in] old      source mesh
/// @param[in] sources  #N where each new vertex comes from (indices into `old`)
/// @param[in] faces    #F×3 new faces, indices into `sources`
/// @throws InvalidInputError for a source or face index out of range.
[[nodiscard]] Mesh resample(const Mesh& old, std::span<const VertexSource> sources,
                            const Faces& faces);

/// Appends to `m` vertices that are blends of its own (as resample() makes them), keeping its
/// faces: the new vertices of an edit in place, with no copy of the mesh.
/// @param[in,out] m        mesh; its #V rows are kept and #N rows appended to each attribute
/// @param[in]     sources  #N where each new vertex comes from (indices into m's #V vertices)
/// @throws InvalidInputError for a source index out of range, before `m` is changed.
void append_resampled(Mesh& m, std::span<const VertexSource> sources);

}  // namespace cgamesh::mesh
