#pragma once
// Private to surgery: small helpers the cut, tear and drill share.

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/union_find.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/mesh/weld.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/local_edit.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

#include "../flat_map.hpp"
#include "../mesh/position_welder.hpp"

namespace cgamesh::surgery {

/// Key of the directed edge a -> b.
[[nodiscard]] inline std::uint64_t directed_key(int a, int b) noexcept {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}
/// Key of the undirected edge {a, b}.
[[nodiscard]] inline std::uint64_t edge_key(int a, int b) noexcept {
  return a < b ? directed_key(a, b) : directed_key(b, a);
}

/// Signed distance of the point x from the plane n·x = d: X·Π with X = up(x) and Π = n + d e∞
/// (cga), or n·x − d (euclidean).
[[nodiscard]] inline double signed_distance(const Eigen::Vector3d& x, const Eigen::Vector3d& n, double d,
                                            const cga::Vector<double>& plane, Predicates predicates) {
  return predicates == Predicates::cga ? cga::scalar_product(cga::up<double>(x), plane) : n.dot(x) - d;
}

/// Length of the bounding-box diagonal of the rows of `points` (0 when empty).
[[nodiscard]] double bounding_diagonal(const mesh::RowMatrixXf<3>& points);

/// A box around the placed model, what tools are measured against (lo > hi when empty).
struct PlacedBox {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  [[nodiscard]] bool empty() const { return !(hi.array() >= lo.array()).all(); }
  [[nodiscard]] double diagonal() const { return empty() ? 0.0 : (hi - lo).norm(); }
};
/// The box of every placed position: O(#V), for operations that are O(#F) anyway.
[[nodiscard]] PlacedBox placed_box(const Placement& placement);
/// The union of the index's tree boxes (every placed face, a little more after edits): O(1) per
/// mesh, so that an operation in place on a large mesh stays local.
[[nodiscard]] PlacedBox placed_box(const SurfaceIndex& index);

/// @throws InvalidInputError naming `what` (e.g. "drill: the tip") when `point` lies farther
///         than kMaxToolReach diagonals from `box`, the placed model's.
void require_in_reach(const PlacedBox& box, const Eigen::Vector3d& point, const std::string& what);
/// @throws InvalidInputError naming `what` when `length` exceeds kMaxToolReach diagonals of
///         `box`, the placed model's.
void require_size_in_reach(const PlacedBox& box, double length, const std::string& what);

using mesh::position_key;
using mesh::PositionHash;
using mesh::PositionWelder;
using mesh::UnionFind;
using mesh::weld_by_position;

/// A unit vector perpendicular to the unit vector n.
[[nodiscard]] Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n);

/// The result of applying a LocalEdit.
struct EditedMesh {
  mesh::Mesh mesh;
  std::vector<mesh::VertexSource> origins;  ///< per vertex of `mesh`: its origin in the old mesh
  mesh::RowMatrixXf<3> placed;              ///< per vertex of `mesh`: its placed position
  std::vector<int> vertex_of;               ///< per extended id: its vertex in `mesh`, or -1
};

/// The removed faces of `edit`, sorted.
/// @throws InvalidInputError for a removed face or a new face's vertex out of range, a face
///         removed twice, or a new face's origin that is neither an old face nor
///         LocalEdit::kCutSurface.
[[nodiscard]] std::vector<int> checked_removed_faces(const mesh::Mesh& old, const LocalEdit& edit);

/// Whether some new face of `edit` gets the cut-surface material.
[[nodiscard]] bool has_cut_surface(const LocalEdit& edit);

/// The material of new face t of `edit` on `old` (LocalEdit::new_face_origins), with
/// `cut_surface` the index of the cut-surface material.
[[nodiscard]] int new_face_material(const mesh::Mesh& old, const LocalEdit& edit, std::size_t t, int cut_surface);

/// L⁻¹ y for the linear part L of a vertex's blended skinning transform (the closed-form 3×3
/// inverse); nothing when that blend of joints collapses space (a zero scale).
[[nodiscard]] std::optional<Eigen::Vector3d> unskin(const Eigen::Matrix3d& l, const Eigen::Vector3d& y);

/// The old faces that are not removed, in their order, then the new faces; vertices no face
/// uses are dropped, the others keep their relative order (old ones first). Faces keep their
/// materials, new ones get theirs by new_face_material (with `cut_surface`): the mesh gets
/// face_materials when they differ.
/// @throws InvalidInputError for an id out of range.
/// New vertices get rest positions by `rest` against `palette` (see solve_rest_positions).
[[nodiscard]] EditedMesh apply_edit(const mesh::Mesh& old, const mesh::RowMatrixXf<3>& placed,
                                    const anim::SkinningPalette& palette, const LocalEdit& edit, RestPosition rest,
                                    int cut_surface = -1);

/// Rest positions of the blended vertices of `m` (rows first + k whose origins[k] is a point on
/// an edge or a face; copies of old vertices keep theirs). `exact`: the solution x of
/// A x + b = p, with A x + b the vertex's blended map (anim::blended_affine) and p its placed
/// position, so that eq. (17) takes it back onto the tool; `parametric`: left as resample()
/// blended them. Rows with off_surface[k] set are solved in any case.
/// @param[in,out] m            the edited mesh, its new vertices' weights already set
/// @param[in]     palette      the `cga` palette the placement was skinned with
/// @param[in]     placed       #V×3 placed positions of m
/// @param[in]     off_surface  empty, or one flag per origin
void solve_rest_positions(mesh::Mesh& m, const anim::SkinningPalette& palette, const mesh::RowMatrixXf<3>& placed,
                          std::span<const mesh::VertexSource> origins, Eigen::Index first, RestPosition rest,
                          std::span<const char> off_surface = {});

/// Sets the rest normal of vertex v of `m` so that skinning turns it into `placed_normal`
/// (anim::skin_normals maps n by the cofactor of the blended linear map L, so n = Lᵀ n′). A zero
/// `placed_normal`, or a mesh without normals, leaves it as it is.
void set_placed_normal(mesh::Mesh& m, const anim::SkinningPalette& palette, Eigen::Index v,
                       const Eigen::Vector3d& placed_normal);

/// Keeps the first `keep` of `warnings` and says how many more there were: a tool through a model
/// of hundreds of small meshes warns about each, and a flood hides what matters.
void bound_warnings(std::vector<std::string>& warnings, std::size_t keep = 12);

/// Faces of all meshes of `model`.
[[nodiscard]] int face_total(const anim::RiggedModel& model);

/// Sets everything of `out` but its meshes (skeleton, clips, load warnings) from `model`: the
/// parts surgery hands on unchanged.
void copy_rig(const anim::RiggedModel& model, anim::RiggedModel& out);

/// @throws InvalidInputError when `placement` does not hold one #V×3 block per mesh of `model`.
void require_placement_fits(const anim::RiggedModel& model, const Placement& placement);

/// @throws InvalidInputError (naming `operation`) when `index` was not built for `model`.
void require_index_fits(const anim::RiggedModel& model, const SurfaceIndex& index, const std::string& operation);

}  // namespace cgamesh::surgery
