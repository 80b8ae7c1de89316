#pragma once
// The spatial and topological index of a placed model that local surgery (tear, drill) walks
// on: built once per placement, reused by any number of operations, so that an operation
// costs what its affected region costs, not what the whole mesh costs.

#include <array>
#include <vector>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/triangle_bvh.hpp"
#include "cgamesh/surgery/placement.hpp"

namespace cgamesh::surgery {

/// The index of one mesh.
struct MeshIndex {
  mesh::TriangleBvh bvh;  ///< over the placed (posed) triangles
  /// #V welded id of each vertex: the smallest index of the vertices at the same rest position,
  /// so seam copies (split for UVs, normals or joints) count as one point of the surface.
  std::vector<int> weld;
  /// #F×3: for each face and edge k (corner k to corner k+1), the face across it, sharing the
  /// welded edge with opposite orientation; -1 on a boundary or a non-manifold edge.
  std::vector<std::array<int, 3>> neighbor;

  /// The edge of face `g` that is edge `k` of its neighbour `f` (−1 when none).
  [[nodiscard]] int edge_across(int f, int k) const noexcept;
};

/// The index of every mesh of a model in one placement.
struct SurfaceIndex {
  std::vector<MeshIndex> meshes;

  /// Builds the BVH of each placed mesh and its welded face adjacency: O(F log F).
  /// @param[in] model      the model the placement was made from
  /// @param[in] placement  place(model, pose)
  /// @throws InvalidInputError when the placement does not fit the model, or holds NaN.
  [[nodiscard]] static SurfaceIndex build(const anim::RiggedModel& model, const Placement& placement);
};

}  // namespace cgamesh::surgery
