#pragma once
// Private to surgery: small helpers the cut, tear and drill share.

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

namespace cgamesh::surgery {

using MeshFaces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Key of the undirected edge {a, b}.
[[nodiscard]] std::uint64_t edge_key(int a, int b) noexcept;
/// Key of the directed edge a -> b.
[[nodiscard]] std::uint64_t directed_key(int a, int b) noexcept;

/// Signed distance of every placed vertex from the plane n·x = d: X·Π with X = up(x) and
/// Π = n + d e∞ (cga), or n·x − d (euclidean).
[[nodiscard]] std::vector<double> signed_distances(const mesh::RowMatrixXf<3>& placed, const Eigen::Vector3d& n, double d,
                                                   const cga::Vector<double>& plane, Predicates predicates);

/// Length of the bounding-box diagonal of the rows of `points` (0 when empty).
[[nodiscard]] double bounding_diagonal(const mesh::RowMatrixXf<3>& points);

/// Welds vertices by exact position, on demand: only the vertices asked about are hashed, so a
/// local operation on a large mesh stays local. Seam copies get the same id (the first of them
/// asked about).
class PositionWelder {
 public:
  explicit PositionWelder(const mesh::RowMatrixXf<3>& positions) : positions_(positions) {}
  [[nodiscard]] int operator()(int v);

 private:
  struct Hash {
    std::size_t operator()(const std::array<float, 3>& p) const noexcept;
  };
  const mesh::RowMatrixXf<3>& positions_;
  std::unordered_map<std::array<float, 3>, int, Hash> first_;
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
  std::vector<int> removed_faces;                ///< old faces dropped (each once)
  std::vector<std::array<int, 3>> new_faces;     ///< over extended ids

  /// Adds a new vertex; returns its extended id.
  int add_vertex(const mesh::VertexSource& source, const Eigen::Vector3d& placed, int old_vertex_count) {
    new_vertices.push_back(source);
    new_placed.push_back(placed);
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

/// The old faces that are not removed, in their order, then the new faces; vertices no face
/// uses are dropped, the others keep their relative order (old ones first).
/// @throws InvalidInputError for an id out of range.
[[nodiscard]] EditedMesh apply_edit(const mesh::Mesh& old, const mesh::RowMatrixXf<3>& placed, const LocalEdit& edit);

/// Sets everything of `out` but its meshes (skeleton, clips, load warnings) from `model`: the
/// parts surgery hands on unchanged.
void copy_rig(const anim::RiggedModel& model, anim::RiggedModel& out);

/// @throws InvalidInputError when `placement` does not hold one #V×3 block per mesh of `model`.
void require_placement_fits(const anim::RiggedModel& model, const Placement& placement);

/// @throws InvalidInputError (naming `operation`) when `index` was not built for `model`.
void require_index_fits(const anim::RiggedModel& model, const SurfaceIndex& index, const std::string& operation);

}  // namespace cgamesh::surgery
