#pragma once
// A deformation spec (spec.hpp) bound to one mesh of a model: the shared steps (the spec's space,
// the reach of its points, the keys) in BoundDeformer, each method's own (the harmonic solve and
// blend weights of paper sections III.A and IV, the lattice of V, the cage of VI, the ARAP
// factorisation of VII) behind BoundMethod, one binder per method (src/deform/*_method.cpp,
// registered once in src/deform/deform_method.cpp). apply() then runs one frame for any keys
// (eq. 2).

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/deform/arap.hpp"
#include "cgamesh/deform/cage_coordinates.hpp"
#include "cgamesh/deform/fabrik.hpp"
#include "cgamesh/deform/ffd.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/deform/spec.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/world_surface.hpp"

namespace cgamesh::deform {

/// The space a spec without "space" acts in: world when some mesh of the model is skinned
/// (boxes from `info` then select what the user sees), mesh otherwise.
[[nodiscard]] DeformSpace default_space(const anim::RiggedModel& model) noexcept;

/// Every mesh of `model` at rest in `space`, as an OBJ or PLY of it holds them (positions and
/// unit normals, per mesh): in mesh space its own positions and normals; in world space the
/// bind pose (matrix skinning, eq. 16; normals by each vertex's cofactor, as anim::skin_normals()).
/// @throws InvalidInputError as anim::make_palette().
[[nodiscard]] mesh::WorldSurface rest_surfaces(const anim::RiggedModel& model, DeformSpace space);

/// rest_surfaces(model, space).positions.
/// @throws InvalidInputError as anim::make_palette().
[[nodiscard]] std::vector<mesh::RowMatrixXf<3>> rest_positions(const anim::RiggedModel& model, DeformSpace space);

struct SpecBindOptions {
  MotorBlendOptions blend;  ///< threads of apply()
};

/// One method bound to one mesh: the per-frame half of a binder (the one small interface every
/// method implements). Its frames run through BoundDeformer, which checks the keys' count first.
class BoundMethod {
 public:
  virtual ~BoundMethod() = default;
  /// The bound lattice (ffd), else null.
  [[nodiscard]] virtual const FreeFormDeformation* ffd() const noexcept { return nullptr; }
  /// The bound cage (cage), else null.
  [[nodiscard]] virtual const CageDeformation* cage() const noexcept { return nullptr; }

 private:
  friend class BoundDeformer;
  /// One frame in the bound space: #V×3 positions under `keys` (as many as the bound keys).
  /// @throws InvalidInputError when a key is not a similarity; SolverError when a solve fails.
  virtual void apply(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out,
                     ArapReport* report) const = 0;
  /// ffd, cage: the control points under `keys` (BoundDeformer::control_points); else empty.
  [[nodiscard]] virtual std::vector<Eigen::Vector3d> control_points(std::span<const cga::Versor<double>> keys) const;
};

/// What a binder resolves besides its BoundMethod: BoundDeformer's accessors.
struct BoundHandles {
  std::vector<cga::Versor<double>> keys;  ///< #n key versors
  std::optional<FabrikResult> ik;
  std::vector<std::vector<int>> handles;  ///< per handle, its mesh vertices
  std::vector<int> free;                  ///< vertices no handle moves, ascending
  std::vector<std::vector<int>> control_handles;
  std::vector<std::array<int, 2>> control_edges;
};

/// A spec bound to one mesh of a model: the selections resolved, the harmonic field solved and
/// the blend weights built once (ffd: the lattice weights); apply() then costs one blend per
/// vertex (eq. 2; ffd: eq. 6 or 7), for the spec's keys or any others.
class BoundDeformer {
 public:
  /// Binds `spec` to mesh `spec.mesh` of `model`: the shared steps here (the space, the reach
  /// of the spec's points), the method's own by its binder. For spline, harmonic and arap,
  /// connected parts without a handle vertex (parts as the harmonic field sees them: welded
  /// positions joined by a non-degenerate triangle) are moved as the spec's `free_parts` says.
  /// @param[in] spec   a parsed spec
  /// @param[in] model  the model; it may be destroyed after binding
  /// @throws InvalidInputError "spec.mesh: ..." for a mesh index out of range; "spec.FIELD: ..."
  ///         for a point (a sphere's or box's, a key's center, an IK joint or target, the lattice
  ///         box's origin) or a length (a sphere's radius, a key's translation, the lattice box's
  ///         size or margin) beyond io::kMaxReach sizes of the mesh (its box in the spec's space);
  ///         "spec.handles[h]:
  ///         ..." for an index out of range, a selection of no vertex or a vertex (or welded
  ///         position) shared with another handle; "spec.handles", "spec.keys" or
  ///         "spec.ik.joints: ..." for a count the method or basis cannot take (harmonic: one key
  ///         per handle; spline: 2 handles, keys as spline_weights() takes them); "spec.ik: ..." when FABRIK refuses
  ///         the chain; "spec.space: ..." for world space on a mesh whose bind skinning is singular at a vertex;
  ///         arap: "spec.handles[h]: ..." as harmonic, SolverError when the factorisation fails;
  ///         ffd: "spec.handles[h]: ..." for a control point outside the lattice or a selection of
  ///         none, "spec.lattice.margin: ..." for a mesh flat along an axis without a margin;
  ///         cage: FileError for a cage, deformed cage or coordinates file that cannot be read,
  ///         "spec.cage: ..." as check_cage() or for a vertex outside the cage (InvalidInputError),
  ///         "spec.deformed_cage: ..." for another topology, "spec.coordinates: ..." for a cache
  ///         of another shape or that cannot be written (WriteError), "spec.handles[h]: ..." for a
  ///         cage vertex out of range or a selection of none;
  ///         SolverError as harmonic_precompute() and cage_coordinates().
  BoundDeformer(const DeformSpec& spec, const anim::RiggedModel& model, const SpecBindOptions& options = {});

  [[nodiscard]] int mesh_index() const noexcept { return mesh_; }
  [[nodiscard]] DeformSpace space() const noexcept { return space_; }
  [[nodiscard]] Eigen::Index vertex_count() const noexcept { return rest_.rows(); }
  /// #n the spec's keys as versors: its key transforms, or the FABRIK motors of its IK chain.
  [[nodiscard]] const std::vector<cga::Versor<double>>& keys() const noexcept { return bound_.keys; }
  /// The FABRIK solution when the spec has an IK chain.
  [[nodiscard]] const std::optional<FabrikResult>& ik() const noexcept { return bound_.ik; }
  /// #V×3 rest positions of the mesh in space() (what apply() deforms and handles select).
  [[nodiscard]] const mesh::RowMatrixXf<3>& rest_positions() const noexcept { return rest_; }
  /// Per handle, its vertex indices in the mesh (sorted for boxes and spheres, as given for
  /// index lists): what a viewer draws, at rest_positions() or at the apply() result.
  [[nodiscard]] const std::vector<std::vector<int>>& handles() const noexcept { return bound_.handles; }
  /// Vertices of the parts that hold no handle vertex, ascending (ffd: outside the lattice box).
  [[nodiscard]] const std::vector<int>& free_vertices() const noexcept { return bound_.free; }
  /// The bound method (its lattice or cage, for what a front end reports).
  [[nodiscard]] const BoundMethod& method() const noexcept { return *method_; }
  /// Per handle, its control point indices (Lattice::index()) for ffd, its cage vertices for cage;
  /// empty otherwise. Such a handle selects no mesh vertex: handles() then holds an empty set per
  /// handle.
  [[nodiscard]] const std::vector<std::vector<int>>& control_handles() const noexcept { return bound_.control_handles; }
  /// ffd: the lattice's edges (neighbours along an axis); cage: the cage's edges; as pairs of
  /// control point indices, each once; empty otherwise. What a viewer draws between control_points().
  [[nodiscard]] const std::vector<std::array<int, 2>>& control_edges() const noexcept { return bound_.control_edges; }
  /// ffd, cage: the control points (lattice points, cage vertices) in space(), each under the keys
  /// of the handles that select it composed in handle order: where `keys` put them (classic: the
  /// points the frame interpolates; motor: each point moved by its motor); empty otherwise.
  /// @param[in] keys  #n key versors, in the order of keys()
  /// @throws InvalidInputError when keys has the wrong size.
  [[nodiscard]] std::vector<Eigen::Vector3d> control_points(std::span<const cga::Versor<double>> keys) const;

  /// One frame: every vertex by its blended motor under `keys` (eq. 2); a free part by its
  /// handle's key (FreeParts::nearest) or not at all (keep). ffd: each control point moved by
  /// the keys of the handles that select it, composed in handle order (identity when none), then
  /// eq. 6 (classic) or eqs. 7-8 (motor); cage: the same for the cage vertices (from the
  /// deformed cage when the spec gives one), then CageDeformation.
  /// arap: each handle's vertices at its key applied to their rest positions, the others by
  /// arap_solve() from the rest shape (eqs. 9-12).
  /// @param[in]  keys    #n key versors (TRS similarities), in the order of keys()
  /// @param[out] out     #V×3 positions in space() (resized)
  /// @param[out] report  arap: the energy per iteration (untouched for the other methods); may be null
  /// @throws InvalidInputError when keys has the wrong size or a key is not a similarity;
  ///         SolverError when the ARAP solve fails.
  void apply(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out, ArapReport* report = nullptr) const;
  /// The same, returned.
  [[nodiscard]] mesh::RowMatrixXf<3> apply(std::span<const cga::Versor<double>> keys) const;

  /// Positions in space() as rest positions in mesh space: in world space each vertex through
  /// the inverse of its blended bind map x ↦ A x + b (eq. 16) — exact, since re-skinning uses the
  /// same per-vertex A and b — so that the edited mesh, skinned in the bind pose, is at `positions`.
  /// @param[in] positions  #V×3, e.g. apply()'s result
  /// @throws InvalidInputError when positions has the wrong size.
  [[nodiscard]] mesh::RowMatrixXf<3> to_mesh_space(const mesh::RowMatrixXf<3>& positions) const;

  /// The model with the mesh's rest shape replaced by `positions` (through to_mesh_space()), its
  /// skin, skeleton and clips kept, so that it re-animates; its normals, when it has any, are
  /// those of the new shape with the old smoothing (mesh::reshaped_normals); its morph targets
  /// turn and stretch with the surface (transport_morph_targets).
  /// @param[in] model      the model bound (same meshes)
  /// @param[in] positions  #V×3 in space()
  /// @throws InvalidInputError when the model does not have the bound mesh's vertex count.
  [[nodiscard]] anim::RiggedModel deformed_model(const anim::RiggedModel& model,
                                                 const mesh::RowMatrixXf<3>& positions) const;

  /// What an OBJ or PLY of the result holds: every mesh of deformed_model(model, positions) at
  /// rest in space() (rest_surfaces()), the bound mesh exactly at `positions`.
  /// @param[in] model      the model bound (same meshes)
  /// @param[in] positions  #V×3 in space()
  /// @throws InvalidInputError as deformed_model().
  [[nodiscard]] mesh::WorldSurface deformed_surfaces(const anim::RiggedModel& model,
                                                   const mesh::RowMatrixXf<3>& positions) const;

  /// Writes the result by the extension of `out` (io::write_model()): deformed_model() as
  /// .glb/.gltf, deformed_surfaces() as .obj/.ply. Atomic.
  /// @return the glTF writer's warnings
  /// @throws InvalidInputError as deformed_model() and io::write_model(); WriteError.
  std::vector<std::string> write(const anim::RiggedModel& model, const mesh::RowMatrixXf<3>& positions,
                                 const std::filesystem::path& out) const;

 private:
  int mesh_ = 0;
  DeformSpace space_ = DeformSpace::mesh;
  mesh::RowMatrixXf<3> rest_;
  BoundHandles bound_;
  std::unique_ptr<const BoundMethod> method_;
  /// World space: #V inverse bind maps [A⁻¹  −A⁻¹ b].
  std::vector<Eigen::Matrix<double, 3, 4>> to_mesh_;
};

}  // namespace cgamesh::deform
