#pragma once
// A placed model under surgery, edited in place: the rigged model, its placement and its
// SurfaceIndex kept together, so that a cut, tear or drill costs what its affected region
// costs, not what copying a million-face mesh costs (as a VR-surgery frame needs).

#include <array>
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/local_edit.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

namespace cgamesh::surgery {

/// What one operation in place changed in one mesh: the map from the edited mesh to the mesh
/// before (geometry-central style), without a copy of either.
/// - Vertices keep their ids; vertices first_new_vertex … #V−1 are new. Old vertices are never
///   removed (one a drill cuts away is left unreferenced) but may move (a tear's opening).
/// - Faces: `new_faces` holds the ids of the new triangles; untouched faces keep their ids,
///   except those in `moved_faces` that filled the slot of a removed face.
struct MeshChange {
  int mesh = -1;                                ///< index into model().meshes
  int first_new_vertex = 0;                     ///< #V before the operation
  std::vector<mesh::VertexSource> origins;      ///< per new vertex: its origin over the vertices before
  std::vector<int> new_faces;                   ///< ids of the new faces in the edited mesh
  std::vector<std::array<int, 2>> moved_faces;  ///< (id before, id after) of untouched faces moved
  int removed_faces = 0;                        ///< faces of the mesh before that are gone
};

/// The result of LiveModel::apply: what changed, and where the edit's new vertices went.
struct AppliedEdit {
  MeshChange change;
  int old_vertex_count = 0;
  std::vector<int> fresh;  ///< per new vertex of the edit: its vertex id, or −1 when no face uses it

  /// The vertex of an extended id (old ids stay).
  [[nodiscard]] int vertex_of(int x) const noexcept {
    return x < old_vertex_count ? x : fresh[static_cast<std::size_t>(x - old_vertex_count)];
  }
};

/// A rigged model placed in one pose, with its SurfaceIndex, that surgery edits in place (the
/// overloads of cut_in_place, tear and drill taking a LiveModel&). The three stay consistent:
/// every vertex has a placed position, and the index covers every face. New vertices get rest
/// positions and skin weights from their origins (section 4.3), so model() re-animates.
/// The mesh arrays, placed positions and index keep a quarter of spare capacity (mesh::RowArray,
/// Mesh::reserve), so that operations grow them without copying a million-face mesh.
class LiveModel {
 public:
  /// Indexes `model` as placed in `placement` (SurfaceIndex::build, O(F log F)).
  /// @throws InvalidInputError when the placement does not fit the model or holds NaN.
  LiveModel(anim::RiggedModel model, Placement placement);
  /// A copy to operate on while keeping this one (as a snapshot to go back to).
  LiveModel(const LiveModel& other);
  LiveModel& operator=(const LiveModel& other);
  LiveModel(LiveModel&&) noexcept = default;
  LiveModel& operator=(LiveModel&&) noexcept = default;
  ~LiveModel() = default;

  [[nodiscard]] const anim::RiggedModel& model() const noexcept { return model_; }
  [[nodiscard]] const Placement& placement() const noexcept { return placement_; }
  [[nodiscard]] const SurfaceIndex& index() const noexcept { return index_; }
  /// Gives the model up (e.g. to write it), leaving this LiveModel empty.
  [[nodiscard]] anim::RiggedModel release() && noexcept { return std::move(model_); }

  /// May move the vertices of an edit's new faces once they are in the mesh (a tear's opening),
  /// before the index is brought up to date.
  using Adjust = std::function<void(const AppliedEdit& applied, mesh::Mesh& mesh, mesh::RowMatrixXf<3>& placed)>;

  /// Applies `edit` to mesh `i` where it is, the building block of the operations in place: new
  /// faces fill the slots of removed faces (the last faces fill any slots left over), used new
  /// vertices are appended with rest positions by `rest` and skin weights from their origins
  /// (section 4.3), and the mesh's SurfaceIndex follows (welds, adjacency, BVH) in O(edit): as a
  /// fresh build would give it, except that copies for different sides of a separation stay
  /// apart. New faces get their materials by edit.new_face_origins() (the cut-surface material is
  /// added to model().materials when first used); the mesh gets Mesh::face_materials (one
  /// O(F) fill) when its faces' materials first differ.
  /// @param[in] i       index into model().meshes
  /// @param[in] edit    over mesh i's vertices (ids below #V) and the edit's new ones
  /// @param[in] adjust  empty, or called once the new vertices are in the mesh
  /// @throws InvalidInputError for a mesh, face or vertex id out of range, a face removed twice,
  ///         or a new face's parent that is not removed, before anything is changed.
  [[nodiscard]] AppliedEdit apply(std::size_t i, const LocalEdit& edit, RestPosition rest, const Adjust& adjust = {});

 private:
  /// Headroom in the mesh arrays, placed positions and index for the faces and vertices
  /// operations add.
  void reserve_headroom();
  anim::RiggedModel model_;
  Placement placement_;
  SurfaceIndex index_;
};

}  // namespace cgamesh::surgery
