#pragma once
// Private to surgery: small helpers the cut, tear and drill share.

#include <array>
#include <cstdint>
#include <functional>
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
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

#include "flat_map.hpp"

namespace cgamesh::surgery {

using MeshFaces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

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

/// Row v of `positions` as a key of its exact position: +0.0f folds -0.0f into 0.0f, whose bits
/// differ.
[[nodiscard]] inline std::array<float, 3> position_key(const mesh::RowMatrixXf<3>& positions, Eigen::Index v) {
  return {positions(v, 0) + 0.0f, positions(v, 1) + 0.0f, positions(v, 2) + 0.0f};
}

/// Hash of a position by its bits.
struct PositionHash {
  std::size_t operator()(const std::array<float, 3>& p) const noexcept;
};

/// Welds vertices by exact position, on demand: only the vertices asked about are hashed, so a
/// local operation on a large mesh stays local. Seam copies get the same id (the first of them
/// asked about).
class PositionWelder {
 public:
  explicit PositionWelder(const mesh::RowMatrixXf<3>& positions) : positions_(positions) {}
  [[nodiscard]] int operator()(int v);

 private:
  const mesh::RowMatrixXf<3>& positions_;
  FlatMap<int, std::array<float, 3>, PositionHash> first_;
};

/// Disjoint sets of 0 … n−1 (union by index, path halving).
class UnionFind {
 public:
  explicit UnionFind(std::size_t n);
  [[nodiscard]] int find(int a) noexcept;
  /// Joins the sets of a and b.
  void unite(int a, int b) noexcept;

 private:
  std::vector<int> parent_;
};

/// Per vertex, the welded id of PositionWelder for the whole mesh.
[[nodiscard]] std::vector<int> weld_by_position(const mesh::RowMatrixXf<3>& positions);

/// A unit vector perpendicular to the unit vector n.
[[nodiscard]] Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n);

/// A local edit of one mesh: some old faces replaced by new faces over extended vertex ids
/// (old vertices 0 … #V−1, then the new vertices #V + i).
struct LocalEdit {
  std::vector<mesh::VertexSource> new_vertices;  ///< where each new vertex comes from (old mesh)
  std::vector<Eigen::Vector3d> new_placed;       ///< placed position of each new vertex
  /// Per new vertex: the side of a separation (cut or tear) it is a copy for, ±1, or 0. Copies
  /// for different sides never weld in the index, though they may share a rest position.
  std::vector<signed char> new_side;
  /// Per new vertex: its placed unit normal where it has one of its own (a hole's wall), else
  /// zero (blended from its origin like its other attributes).
  std::vector<Eigen::Vector3d> new_normal;
  /// Per new vertex: whether it lies off the input surface (a blind hole's wall), so that its
  /// rest position can only come from its placed one (always solved, whatever RestPosition).
  std::vector<char> new_off_surface;
  std::vector<int> removed_faces;             ///< old faces dropped (each once)
  std::vector<std::array<int, 3>> new_faces;  ///< over extended ids
  /// Per new face: the removed face it lies in, when every new face has one (it may fill that
  /// face's slot in place); empty otherwise.
  std::vector<int> new_face_parent;

  /// Adds a new vertex; returns its extended id.
  int add_vertex(const mesh::VertexSource& source, const Eigen::Vector3d& placed, int old_vertex_count,
                 signed char side = 0, const Eigen::Vector3d& normal = Eigen::Vector3d::Zero(),
                 bool off_surface = false) {
    new_vertices.push_back(source);
    new_placed.push_back(placed);
    new_side.push_back(side);
    new_normal.push_back(normal);
    new_off_surface.push_back(off_surface ? 1 : 0);
    return old_vertex_count + static_cast<int>(new_vertices.size()) - 1;
  }
};

/// The result of applying a LocalEdit.
struct EditedMesh {
  mesh::Mesh mesh;
  std::vector<mesh::VertexSource> origins;  ///< per vertex of `mesh`: its origin in the old mesh
  mesh::RowMatrixXf<3> placed;              ///< per vertex of `mesh`: its placed position
  std::vector<int> vertex_of;               ///< per extended id: its vertex in `mesh`, or -1
};

/// The removed faces of `edit`, sorted.
/// @throws InvalidInputError for a removed face or a new face's vertex out of range, a face
///         removed twice, or a new vertex without a placed position.
[[nodiscard]] std::vector<int> checked_removed_faces(const mesh::Mesh& old, const LocalEdit& edit);

/// The old faces that are not removed, in their order, then the new faces; vertices no face
/// uses are dropped, the others keep their relative order (old ones first).
/// @throws InvalidInputError for an id out of range.
/// New vertices get rest positions by `rest` against `palette` (see solve_rest_positions).
[[nodiscard]] EditedMesh apply_edit(const mesh::Mesh& old, const mesh::RowMatrixXf<3>& placed,
                                    const anim::SkinningPalette& palette, const LocalEdit& edit, RestPosition rest);

namespace detail {

/// The parts of a LiveModel the operations in place edit.
struct LiveAccess {
  static mesh::Mesh& mesh(LiveModel& live, std::size_t i) { return live.model_.meshes[i]; }
  static mesh::RowMatrixXf<3>& placed(LiveModel& live, std::size_t i) { return live.placement_.positions[i]; }
  static MeshIndex& index(LiveModel& live, std::size_t i) { return live.index_.meshes[i]; }
};

}  // namespace detail

/// The result of applying a LocalEdit in place.
struct AppliedEdit {
  MeshChange change;
  int old_vertex_count = 0;
  std::vector<int> fresh;  ///< per new vertex of the edit: its vertex id, or −1 when no face uses it

  /// The vertex of an extended id (old ids stay).
  [[nodiscard]] int vertex_of(int x) const noexcept {
    return x < old_vertex_count ? x : fresh[static_cast<std::size_t>(x - old_vertex_count)];
  }
};

/// Applies `edit` to mesh `i` of `live` where it is: new faces fill the slots of removed faces
/// (the last faces fill any slots left over), used new vertices are appended, and the mesh's
/// SurfaceIndex follows (welds, adjacency, BVH) in O(edit): as a fresh build would give it,
/// except that copies for different sides of a separation stay apart.
/// `adjust`, when given, may move the vertices of the new faces (a tear's opening) once they are
/// in the mesh, before the index is brought up to date.
/// @throws InvalidInputError for an id out of range or a new face's parent that is not removed,
///         before anything is changed.
[[nodiscard]] AppliedEdit apply_edit_in_place(LiveModel& live, std::size_t i, const LocalEdit& edit, RestPosition rest,
                                              const std::function<void(const AppliedEdit&)>& adjust = {});

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
