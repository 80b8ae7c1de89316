#pragma once
// Tearing a skinned model with a moving scalpel (paper Algorithm 2): a partial cut along the
// surface path the blade sweeps, opened so the model animates again with the tear in it.

#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

namespace cgamesh::surgery {

/// The blade at one time step: a segment from the handle (outside the body) to the tip.
struct Scalpel {
  Eigen::Vector3d handle;
  Eigen::Vector3d tip;
};

struct TearOptions {
  /// Opening width: the two copies of every path vertex move apart along ±Π's normal (the
  /// paper's step 6), by open·sin(π s/L) in all at arc length s of a tear of length L, so the
  /// tear closes smoothly at its two ends. 0 leaves the surface in place, split along the path.
  double open = 0;
  /// The copy of a new vertex on each side of the tear takes only the influences of the old
  /// vertices on its own side of Π (paper section 4.3, "variations").
  bool own_side_influences = false;
  /// Points closer than this (times the placed mesh's bounding-box diagonal) to a vertex or an
  /// edge are moved onto it: no sliver triangles, no duplicate points.
  double snap = 1e-6;
  /// Rest positions of new vertices: on the tool when re-posed at the operation's pose
  /// (`exact`), or the paper's edge/face parameters on the rest mesh.
  RestPosition rest = RestPosition::exact;
  Predicates predicates = Predicates::cga;
};

/// What a tear did, in place or as a copy.
struct TearStats {
  /// The surface path S₀, Q…, S₁, Q…, …, Sₖ in placed coordinates, in order.
  std::vector<Eigen::Vector3d> path;
  int new_vertices = 0;             ///< vertices added to the torn mesh
  int intersection_points = 0;      ///< points of the path (entry points S and crossings Q)
  int faces_in = 0, faces_out = 0;  ///< faces of the whole model before and after
  int faces_split = 0;              ///< input faces re-triangulated
  std::vector<std::string> warnings;
};

/// A torn model: the torn mesh replaced, everything else (other meshes, skeleton, clips) kept.
struct ModelTear : TearStats {
  anim::RiggedModel model;
  int mesh = -1;  ///< index of the torn mesh in `model.meshes`
  /// Per vertex of the torn mesh: its origin in the input mesh (old vertex, point on an old
  /// edge, or point inside an old face). Opened copies are then moved by the opening.
  std::vector<mesh::VertexSource> origins;
  mesh::RowMatrixXf<3> placed;  ///< #V×3 placed positions of the torn mesh (opened)
  /// #V: +1 or −1 for a copy of a path vertex on the positive or negative side of its step's
  /// plane Π, 0 for every other vertex (and the two ends of the tear).
  std::vector<signed char> side;
};

/// A tear made in place in a LiveModel.
struct LiveTear : TearStats {
  MeshChange change;  ///< the torn mesh and what changed in it
  /// Every copy of a path vertex (vertex id) with its side, +1 or −1, of its step's plane Π.
  std::vector<std::pair<int, signed char>> sides;
};

/// Tears `model` along the path a scalpel sweeps over successive time steps (Algorithm 2): per
/// step i → i+1, the entry points Sᵢ, Sᵢ₊₁ of the blade on the placed surface, the plane Π
/// through Sᵢ and the blade at tᵢ₊₁ (dual of Sᵢ ∧ Hᵢ₊₁ ∧ Tᵢ₊₁ ∧ e∞), the shorter surface path
/// from Sᵢ to Sᵢ₊₁ along Π (sides by X·Π), the faces it crosses re-triangulated, and every path
/// vertex but the two ends of the tear duplicated so the surface opens. The steps continue one
/// tear (progressive tearing). New vertices get skin weights per section 4.3; both copies of a
/// path vertex get the same ones (unless `own_side_influences`).
/// @param[in] model      rigged model
/// @param[in] placement  its placed surface (place())
/// @param[in] index      SurfaceIndex::build(model, placement)
/// @param[in] scalpel    #steps ≥ 2 blade positions at t₀ … tₖ
/// @throws InvalidInputError for fewer than 2 steps, NaN, a blade of zero length, a blade
///         point beyond kMaxToolReach model sizes, a negative opening, or an index that does
///         not fit.
/// @throws TopologyError when the blade misses the surface at a step, or the surface path
///         between two entry points cannot be followed (different parts, an open border), or
///         the tear would change nothing (a path along edges the mesh has split already, and
///         no opening).
[[nodiscard]] ModelTear tear(const anim::RiggedModel& model, const Placement& placement, const SurfaceIndex& index,
                             std::span<const Scalpel> scalpel, const TearOptions& options = {});

/// The same tear in place: the torn mesh of `live` is edited where it is (faces replaced, new
/// vertices appended, its SurfaceIndex updated), so the cost is that of the torn region.
/// @throws as above; on a throw `live` is unchanged.
LiveTear tear(LiveModel& live, std::span<const Scalpel> scalpel, const TearOptions& options = {});

/// As above, building the index first.
[[nodiscard]] ModelTear tear(const anim::RiggedModel& model, const Placement& placement,
                             std::span<const Scalpel> scalpel, const TearOptions& options = {});

}  // namespace cgamesh::surgery
