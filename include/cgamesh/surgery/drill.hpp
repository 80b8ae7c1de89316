#pragma once
// Drilling a skinned model with a finite cylindrical drill (paper Algorithm 3, eqs. 18–20) into
// a model with a hole that animates again.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

namespace cgamesh::surgery {

/// Largest DrillOptions::min_rim_points: a rim of this many chords is a circle to 3·10⁻⁷ of its radius.
inline constexpr int kMaxRimPoints = 4096;
/// Largest DrillOptions::max_refinements: 4¹² times finer faces than the input's.
inline constexpr int kMaxRefinements = 12;

struct DrillOptions {
  /// Line the hole with a tube between each entry rim and the exit rim that follows it along
  /// the axis (where no other surface crosses the axis between them), and a blind hole (an
  /// entry rim with no exit before the tip, the material going on past the tip) with a tube
  /// down to the tip's disk and that disk, so that a closed input stays closed (beyond the
  /// paper). Walls stay inside the material: every other rim (at a mesh boundary, cut by an end
  /// disk, on a sheet, or before the drill leaves the body short of its tip) is left open with a
  /// warning naming it, and counted in DrillStats::open_rims.
  /// Wall faces get the cut-surface material (mesh::cut_surface_material_index, added to the
  /// model's materials when a wall is made); the faces around the hole keep their own.
  bool wall = false;
  /// A rim with fewer points than this (or a disk lying inside one face) is too coarse: the
  /// faces the rim crosses are split 1→4 (red-green, no T-junctions) and drilled again (paper
  /// section 4.2.3). A chord replacing more than 4π / min_rim_points of the circle counts as
  /// too coarse as well (the polygon would reach towards the axis). 3 … kMaxRimPoints.
  int min_rim_points = 6;
  /// At most this many rounds of splitting (0 … kMaxRefinements); a rim still too coarse then
  /// gets a warning.
  int max_refinements = 6;
  /// The work budget of refinement: no round starts that could take the drilled region (the
  /// faces pulled in from the mesh and those splitting made) past this many faces; a warning
  /// says when it stopped refinement. Bounds time and memory whatever the other options.
  int max_region_faces = 20000;
  /// Vertices closer to the cylinder than this (times the placed mesh's bounding-box diagonal)
  /// count as on it: no sliver triangles, no points twice.
  double snap = 1e-6;
  /// Rest positions of new vertices: on the tool when re-posed at the operation's pose
  /// (`exact`), or the paper's edge/face parameters on the rest mesh.
  RestPosition rest = RestPosition::exact;
  Predicates predicates = Predicates::cga;
};

/// What a drill did, in place or as a copy.
struct DrillStats {
  int new_vertices = 0;         ///< output vertices that are not copies of input vertices
  int intersection_points = 0;  ///< rim points on crossed edges (one per edge and seam side)
  int faces_in = 0, faces_out = 0;
  int faces_removed = 0;   ///< input faces replaced (re-triangulated, split or dropped)
  int faces_affected = 0;  ///< faces of the (refined) surface the drill reaches
  int refinements = 0;     ///< rounds of 1→4 splitting, over all meshes
  int wall_triangles = 0;
  int rims = 0;       ///< boundary loops (or chains, where the hole meets a mesh boundary) of the holes
  int walls = 0;      ///< tubes joining an entry rim to an exit rim, and blind holes' walls
  int open_rims = 0;  ///< rims left open with `wall` (each named in a warning)
  std::vector<std::string> warnings;
};

/// A drilled model: the skeleton and clips of the input; meshes the drill does not reach are
/// copied, a mesh drilled away entirely is left out.
struct ModelDrill : DrillStats {
  anim::RiggedModel model;
  /// Per output mesh: the input mesh it came from, the origin of each of its vertices, and the
  /// #V×3 placed positions of its vertices.
  std::vector<int> source_mesh;
  std::vector<std::vector<mesh::VertexSource>> origins;
  std::vector<mesh::RowMatrixXf<3>> placed;
};

/// A drill made in place in a LiveModel.
struct LiveDrill : DrillStats {
  std::vector<MeshChange> changes;  ///< one per mesh the drill reached
};

/// Drills `model`, placed in `placement`, with the finite cylinder of radius `radius` around
/// the axis from `base` B to `tip` A. As in Algorithm 3, a point is inside when its projection
/// onto the plane Π ⟂ AB through B is closer to B than r — and, the drill being finite, when
/// its height above Π lies between 0 and |AB|. Every face of every mesh that meets the cylinder
/// is affected (found through the BVH, whether the axis pierces it or only grazes it), so the
/// hole goes through every surface layer the drill body reaches and stops at the tip: a tip
/// inside the material makes a blind hole, whose bottom is cut at the tip's disk. Each crossed
/// edge gets its intersection points with the cylinder from the quadratic Kα² + Lα + N = 0 of
/// eqs. (18)–(20) (a double root is a touch, not a hole) and with the end disks' planes; the
/// part of each affected face outside the drill is re-triangulated (the arcs become chords)
/// and the rest removed. New vertices are points on old edges or faces, weighted as in
/// section 4.3.
/// Cost: the affected region, not the mesh (apart from assembling the output meshes).
/// @param[in] index   SurfaceIndex::build(model, placement)
/// @param[in] tip, base  world-space end points A and B of the drill axis
/// @throws InvalidInputError for radius <= 0 or NaN, tip == base, non-finite points, a tip,
///         base or radius beyond kMaxToolReach model sizes, bad options, or a placement or
///         index that does not fit the model.
/// @throws TopologyError when the cylinder meets no face (the drill misses; the message says
///         when it stops short of the surface or points away from it), or the drill changes
///         nothing (it lies inside a face even after refinement).
[[nodiscard]] ModelDrill drill(const anim::RiggedModel& model, const Placement& placement, const SurfaceIndex& index,
                               const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius,
                               const DrillOptions& options = {});

/// The same drill in place: each mesh it reaches is edited where it is (faces replaced, new
/// vertices appended, its SurfaceIndex updated), so the cost is that of the drilled region. A
/// mesh drilled away entirely stays, with no faces. The vertices the hole removes stay in their
/// meshes, unreferenced.
/// @throws as above; on a throw `live` is unchanged.
LiveDrill drill(LiveModel& live, const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius,
                const DrillOptions& options = {});

/// The same, building the SurfaceIndex first (O(F log F)); build it once and use the overload
/// above to drill a placed model many times.
[[nodiscard]] ModelDrill drill(const anim::RiggedModel& model, const Placement& placement, const Eigen::Vector3d& tip,
                               const Eigen::Vector3d& base, double radius, const DrillOptions& options = {});

}  // namespace cgamesh::surgery
