#pragma once
// Living tissue (Kamarianakis & Papagiannakis §5, their next step): the skinned surface of a
// surgery::LiveModel as an XPBD soft body (Macklin, Müller & Chentanez 2016, with small steps,
// Macklin et al. 2019), so that cuts, tears and drills open, sag and keep animating.
//
// Particles are the surface's vertices welded by position (a seam is no crack), with lumped
// masses (area × density). Each is attached to its target, its skinned position in the current
// pose (eq. 17, the placement surgery uses); stretch and bending links take their rest values
// from the skinned targets every substep (shortened by the pre-tension), so animation never
// fights the simulation. Only a region around the wounds is simulated: elsewhere the tissue is
// the skinned surface, and a step costs what the region holds.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/row_array.hpp"
#include "cgamesh/soft/chunked_array.hpp"
#include "cgamesh/soft/reach_queue.hpp"
#include "cgamesh/soft/tissue_options.hpp"
#include "cgamesh/surgery/live_model.hpp"

namespace cgamesh::soft {

/// What settle() did.
struct SettleReport {
  double seconds = 0;    ///< simulated time
  int substeps = 0;
  double max_speed = 0;  ///< of any particle at the end (model units per second)
  bool settled = false;  ///< max_speed fell below the tolerance
};

/// The soft-tissue state of one LiveModel. The LiveModel is passed to each call (not kept), as
/// it is edited in place between them; pass the same one, and every change it made through
/// follow().
class Tissue {
 public:
  /// Lumped masses of every vertex (the area of the faces around it / 3 × density, on the
  /// placed surface); no region yet, so nothing is simulated.
  /// @throws InvalidInputError as TissueOptions::validate().
  explicit Tissue(const surgery::LiveModel& live, const TissueOptions& options = {});

  [[nodiscard]] const TissueOptions& options() const noexcept { return options_; }
  /// New options for the tissue as it is (a viewer's sliders): masses follow the density, the
  /// wounds' regions and releases the new radii; positions and velocities are kept.
  /// @throws InvalidInputError as TissueOptions::validate() (the tissue is then unchanged).
  void set_options(const surgery::LiveModel& live, const TissueOptions& options);

  /// Follows an in-place cut, tear or drill (its MeshChanges), in time proportional to the
  /// change and the region: new vertices get masses from their origins (the total is
  /// conserved), positions and velocities interpolated from their origins' (no pop); the region
  /// grows by region_radius around the new vertices, whose neighbourhood (release_margin) is
  /// released from its attachments; links of removed faces go, those of new faces come.
  /// @throws InvalidInputError when a change does not fit the model.
  void follow(const surgery::LiveModel& live, std::span<const surgery::MeshChange> changes);

  /// Adds the vertices of mesh `mesh` within `radius` of `center` (placed) to the region, as
  /// wounds do, without releasing them.
  /// @throws InvalidInputError for a mesh out of range or a negative or NaN radius.
  void select(const surgery::LiveModel& live, int mesh, const Eigen::Vector3d& center, double radius);

  /// Advances the tissue by `dt` seconds towards `pose` (targets interpolated from the last
  /// pose over the substeps), in substeps of options().substep (the remainder carried over).
  /// @throws InvalidInputError for a negative or non-finite dt; SolverError when the state
  ///         diverges (it is then as before the call).
  void step(const surgery::LiveModel& live, const anim::Pose& pose, double dt);

  /// Steps in `pose` until every particle is slower than `tolerance` × the model's diagonal per
  /// second, or `max_seconds` have passed.
  /// @throws as step().
  SettleReport settle(const surgery::LiveModel& live, const anim::Pose& pose, double max_seconds = 5.0,
                      double tolerance = 1e-3);

  /// The surface now: per mesh, #V×3 world positions, the skinned ones in `pose` outside the
  /// region and the simulated ones inside it.
  [[nodiscard]] std::vector<mesh::RowMatrixXf<3>> positions(const surgery::LiveModel& live,
                                                            const anim::Pose& pose) const;

  /// Overwrites the rows of mesh `mesh`'s simulated vertices in `positions` (#V×3 floats, row
  /// after row: the mesh skinned in the pose of the last step, e.g. into an engine's buffer) with
  /// the simulated positions, as positions() gives them, without placing every mesh.
  /// @throws InvalidInputError for a mesh out of range or a span of another size.
  void overlay(const surgery::LiveModel& live, int mesh, std::span<float> positions) const;

  /// The model with the simulated surface written back as rest positions through the inverse
  /// of each vertex's skinning in `pose` (as surgery's exact rest positions are solved), so
  /// that it animates with the wound as simulated: skinned in `pose`, it is positions(pose).
  [[nodiscard]] anim::RiggedModel bake(const surgery::LiveModel& live, const anim::Pose& pose) const;

  [[nodiscard]] double total_mass() const noexcept;
  /// Σ m·v over the simulated particles (kg · model units per second).
  [[nodiscard]] Eigen::Vector3d momentum() const noexcept;
  /// Simulated (free) particles.
  [[nodiscard]] std::size_t free_particles() const noexcept;
  /// All particles of the region (free and those pinned at its border).
  [[nodiscard]] std::size_t particles() const noexcept { return x_.size(); }
  [[nodiscard]] std::size_t links() const noexcept { return link_count_; }

 private:
  struct Link {
    int a, b;     ///< particles
    float scale;  ///< rest length: scale × the skinned distance
    float compliance;
  };
  struct VertexRef {
    int mesh, vertex;  ///< the particle's representative vertex (its weld class's)
  };
  struct Member {
    int mesh, vertex, particle;  ///< a vertex of the region and its particle
  };
  /// A ball of the region around a wound's vertex (followed as the model is placed again) or
  /// around a fixed point (vertex −1).
  struct Ball {
    int mesh;
    int vertex;
    Eigen::Vector3d point;
    double radius;
    [[nodiscard]] Eigen::Vector3d center(const surgery::Placement& placed) const;
  };

  /// Writes the particles' state back to their vertices and empties the region's particles.
  void save_state();
  /// The balls of mesh `mesh` as (centre, 1 / radius²).
  [[nodiscard]] static std::vector<Eigen::Vector4d> spheres(const std::vector<Ball>& balls, int mesh,
                                                            const surgery::Placement& placed);
  /// The least over `spheres` of |p − centre| / radius.
  [[nodiscard]] static double reach(const std::vector<Eigen::Vector4d>& spheres, const Eigen::Vector3d& p);
  /// reach(region_spheres_[mesh], placed vertex v of `mesh`), computed once per region query
  /// (reach_mark_, VertexState::reach).
  [[nodiscard]] float vertex_reach(const surgery::LiveModel& live, std::size_t mesh, int v);
  /// Per mesh, the faces of the region (nearest first) within options().max_particles; sets scale_ and
  /// marks them in face_mark_ with mark_.
  [[nodiscard]] std::vector<std::vector<int>> region_faces(const surgery::LiveModel& live);
  /// Particles and links of the region (the faces in its balls), from the per-vertex state.
  void rebuild(const surgery::LiveModel& live);
  /// Orders the links colour by colour (no two links of a colour share a particle) and makes
  /// their constants.
  void order_links();
  /// Skinned target of every particle in `pose` (palettes made once).
  void targets_in(const surgery::LiveModel& live, const anim::Pose& pose, std::vector<Eigen::Vector3d>& out) const;
  /// One XPBD substep of length h towards the targets `alpha` of the way from `from` to `to`
  /// (those of the step's start and end).
  void substep(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to, double alpha,
               double h);

  TissueOptions options_;
  double radius_ = 0, margin_ = 0, diagonal_ = 0;
  std::vector<Ball> balls_;     ///< the region: faces in these
  std::vector<Ball> releases_;  ///< particles in these have no attachment
  /// What the tissue keeps of each vertex, in one record: one array grows with the mesh, and
  /// a vertex the region visits is one or two cache lines.
  struct VertexState {
    Eigen::Vector3d x = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();  ///< last known position and velocity
    double mass = 0;
    int particle = -1;  ///< −1: not in the region
    /// The save_state() that wrote x and v (0: never): a vertex that left the region and comes
    /// back has no state (its old one is from another time).
    int saved = 0;
    /// As a weld class's representative: the rebuild (mark_) that made its particle, and the particle.
    std::array<int, 2> cls{0, -1};
    int reach_mark = 0;  ///< the region query of `reach`
    float reach = 0;     ///< in single precision, as the region's faces are ordered by it (region_faces())
  };
  std::vector<ChunkedArray<VertexState>> state_;  ///< per mesh, per vertex
  int generation_ = 0;
  /// The factor every ball is shrunk by to keep the region within the budget (1: none).
  double scale_ = 1;
  std::vector<ChunkedArray<int>> face_mark_;  ///< per mesh, per face: the region query that saw it
  std::vector<std::vector<Eigen::Vector4d>> region_spheres_;  ///< per mesh, the region's balls of the last query
  int mark_ = 0, reach_mark_ = 0;
  // Scratch of region_faces(), kept for their capacity: candidate faces (mesh, face) and the
  // queue of their keys.
  std::vector<std::pair<int, int>> candidates_;
  ReachQueue queue_;
  // Per particle.
  std::vector<VertexRef> ref_;
  std::vector<Member> members_;
  std::vector<Eigen::Vector3d> x_, v_, previous_target_, scratch_;
  std::vector<double> inverse_mass_, attach_gain_;
  std::vector<char> free_, attached_;
  std::vector<Link> links_;  ///< colour by colour, each padded to a multiple of 4 (order_links())
  std::size_t link_count_ = 0;  ///< without the padding
  std::vector<std::array<int, 2>> ends_;  ///< per link, as in links_: its particles (what substeps read)
  std::vector<std::size_t> colour_begin_;  ///< first link of each colour, and the end (#colours + 1)
  /// Per link, as in links_ (packets read them): 1 / (w_a + w_b + compliance / substep²), 0 for padding.
  std::vector<float> link_gain_;
  std::vector<float> length2_, correction_;  ///< per link, a substep's |d|² and Δλ/|d|
  /// Per link, scale·(t_a − t_b) at the step's start and its change over the step (#links×6).
  Eigen::ArrayXXf rest_;
  double carried_ = 0;  ///< simulated time owed from the last step (< substep)
  bool have_targets_ = false;
};

}  // namespace cgamesh::soft
