#pragma once
// A placed model under surgery, edited in place: the rigged model, its placement and its
// SurfaceIndex kept together, so that a cut, tear or drill costs what its affected region
// costs, not what copying a million-face mesh costs (as a VR-surgery frame needs).

#include <array>
#include <utility>
#include <vector>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

namespace cgamesh::surgery {

namespace detail {
struct LiveAccess;  // the operations in place (src/surgery)
}  // namespace detail

/// What one operation in place changed in one mesh: the map from the edited mesh to the mesh
/// before (geometry-central style), without a copy of either.
/// - Vertices keep their ids; vertices first_new_vertex … #V−1 are new. Old vertices are never
///   removed (one a drill cuts away is left unreferenced) but may move (a tear's opening).
/// - Faces: `new_faces` holds the ids of the new triangles; untouched faces keep their ids,
///   except those in `moved_faces` that filled the slot of a removed face.
struct MeshChange {
  int mesh = -1;                            ///< index into model().meshes
  int first_new_vertex = 0;                 ///< #V before the operation
  std::vector<mesh::VertexSource> origins;  ///< per new vertex: its origin over the vertices before
  std::vector<int> new_faces;               ///< ids of the new faces in the edited mesh
  std::vector<std::array<int, 2>> moved_faces;  ///< (id before, id after) of untouched faces moved
  int removed_faces = 0;                    ///< faces of the mesh before that are gone
};

/// A rigged model placed in one pose, with its SurfaceIndex, that surgery edits in place (the
/// overloads of cut_in_place, tear and drill taking a LiveModel&). The three stay consistent:
/// every vertex has a placed position, and the index covers every face. New vertices get rest
/// positions and skin weights from their origins (section 4.3), so model() re-animates.
/// Growing a mesh by a few vertices reallocates its arrays (Eigen matrices have no spare
/// capacity): a copy for a block on the heap, a page remap for an mmapped one. On meshes of a
/// million faces the copies are most of an operation's time unless large blocks are mmapped
/// (glibc: a fixed mmap threshold, e.g. GLIBC_TUNABLES=glibc.malloc.mmap_threshold=131072);
/// measured in BENCHMARKS.md.
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

 private:
  friend struct detail::LiveAccess;
  /// Headroom in the index's arrays for the faces and vertices operations add.
  void reserve_headroom();
  anim::RiggedModel model_;
  Placement placement_;
  SurfaceIndex index_;
};

}  // namespace cgamesh::surgery
