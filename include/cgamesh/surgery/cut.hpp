#pragma once
// Cutting a skinned model with a plane (paper Algorithm 1) into two models that animate again.

#include <array>
#include <string>
#include <vector>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/placement.hpp"

namespace cgamesh::surgery {

struct CutOptions {
  /// Close each piece: triangulate every closed cross-section loop (with holes) in the plane,
  /// so each piece of a closed input is closed again (beyond the paper). The cap faces get the
  /// cut-surface material (mesh::cut_surface_material_index, added to the pieces' materials
  /// when a cap is made).
  bool cap = false;
  /// New vertices take only the influences of the old vertices on their own piece's side
  /// (paper section 4.3, "variations"); the two copies of a seam vertex then differ.
  bool own_side_influences = false;
  /// Vertices closer to the plane than this (times the placed mesh's bounding-box diagonal)
  /// count as on it: no sliver triangles, no duplicate points.
  double snap = 1e-6;
  /// Rest positions of new vertices: on the tool when re-posed at the operation's pose
  /// (`exact`), or the paper's edge/face parameters on the rest mesh.
  RestPosition rest = RestPosition::exact;
  Predicates predicates = Predicates::cga;
};

/// One mesh cut in two. Piece 0 is the side n·x > d (the plane's normal points into it).
struct MeshCut {
  std::array<mesh::Mesh, 2> pieces;
  /// Per piece, per vertex: its origin in the input mesh (old vertex, or point on an old edge).
  std::array<std::vector<mesh::VertexSource>, 2> origins;
  /// Per piece, #V×3 placed (posed) positions of its vertices.
  std::array<mesh::RowMatrixXf<3>, 2> placed;
  int intersection_points = 0;  ///< new vertices on crossed edges (one per edge and seam side)
  int faces_split = 0;          ///< input faces re-triangulated
  int cap_triangles = 0;        ///< triangles added by `cap`, both pieces together
  std::vector<std::string> warnings;
};

/// Cuts one mesh placed at `placed` by the plane Π = n + d e∞ (eq. 5): every face crossed is
/// re-triangulated at the intersection points of its edges, X·Π deciding the side of each
/// vertex and (B·Π) A − (A·Π) B the crossing point of edge AB (the meet of line and plane).
/// Faces lying in the plane go to the side their normal faces away from. The pieces' faces keep
/// their materials; cap faces (options.cap) come last and get `cap_material` (the pieces get
/// Mesh::face_materials when the two differ).
/// @param[in] mesh    rest mesh with optional skin, #V vertices
/// @param[in] placed  #V×3 posed positions the plane is placed against
/// @param[in] plane   a CGA plane (cga::plane(n, d))
/// @param[in] palette the `cga` skinning palette `placed` came from (Placement::palettes): new
///                    vertices then get rest positions by options.rest; without it (nullptr)
///                    they keep the parametric ones
/// @param[in] cap_material  material index of the cap faces (the model's cut-surface material,
///                    as cut() passes it), or −1 for none
/// @throws InvalidInputError for a vector that is not a plane, or NaN positions.
[[nodiscard]] MeshCut cut_mesh(const mesh::Mesh& mesh, const mesh::RowMatrixXf<3>& placed,
                               const cga::Vector<double>& plane, const CutOptions& options = {},
                               const anim::SkinningPalette* palette = nullptr, int cap_material = -1);

/// What a cut did, in place or as a copy.
struct CutStats {
  int new_vertices = 0, intersection_points = 0, faces_in = 0, faces_split = 0, cap_triangles = 0;
  std::vector<std::string> warnings;
};

/// A model cut in two: both pieces keep the skeleton and clips; each has the pieces of the
/// meshes that reach its side.
struct ModelCut : CutStats {
  std::array<anim::RiggedModel, 2> pieces;
  /// Per piece, per mesh: the input mesh it came from, its vertex origins, and the placed
  /// positions of its vertices.
  std::array<std::vector<int>, 2> source_mesh;
  std::array<std::vector<std::vector<mesh::VertexSource>>, 2> origins;
  std::array<std::vector<mesh::RowMatrixXf<3>>, 2> placed;
  std::array<int, 2> faces_out{0, 0};
};

/// A cut made in place in a LiveModel: the two pieces stay in their meshes, side by side and
/// no longer connected.
struct LiveCut : CutStats {
  std::vector<MeshChange> changes;  ///< one per mesh the plane crosses or touches
  /// Per change, per new face: its piece (0: the side n·x > d, 1: the other side).
  std::vector<std::vector<signed char>> piece_of_new_face;
  int faces_out = 0;
};

/// The plane n·x = d as a CGA plane Π = n + d e∞ (cga::plane), for any length of n: n and d are
/// first divided by n's largest component, so that huge values do not overflow n's norm. Piece 0
/// of a cut is the side n·x > d. The CLI's --plane, viewer sessions and Python all read a plane so.
/// @throws InvalidInputError for a NaN or infinite value, a zero normal, or an offset too large
///         for its normal.
[[nodiscard]] cga::Vector<double> cut_plane(const Eigen::Vector3d& normal, double d);

/// Cuts every mesh of `model`, placed in `placement` (see place()).
/// @throws InvalidInputError as cut_mesh, or when the placement does not fit the model.
/// @throws TopologyError when the plane misses the model (one piece would be empty).
[[nodiscard]] ModelCut cut(const anim::RiggedModel& model, const Placement& placement, const cga::Vector<double>& plane,
                           const CutOptions& options = {});

/// Both pieces of a cut as one model (`cut -o OUT` with one output, a viewer's capped cut): piece
/// A's meshes, then piece B's. Both come from one model, so they share skeleton, clips and
/// textures; B's materials are appended when its list differs (a cap material only one got).
[[nodiscard]] anim::RiggedModel join_pieces(std::array<anim::RiggedModel, 2> pieces);

/// Cuts `live` in place with the plane Π = n + d e∞: the faces Π crosses are re-triangulated
/// as cut() does, and every vertex on Π (old, or new on a crossed edge) gets one copy per side,
/// so each mesh falls apart into its two pieces where it is. Only the faces near Π are visited
/// (through the BVH): the cost is that of the cross-section, not of the mesh. Untouched faces
/// keep their piece by the side of their vertices; new faces are listed with theirs.
/// @throws InvalidInputError for a vector that is not a plane, or `cap` (use cut() for closed
///         pieces).
/// @throws TopologyError when the plane crosses no face (nothing to separate) or only touches
///         the surface (one side would get no face); `live` is then unchanged.
LiveCut cut(LiveModel& live, const cga::Vector<double>& plane, const CutOptions& options = {});

}  // namespace cgamesh::surgery
