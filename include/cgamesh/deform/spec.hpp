#pragma once
// The deformation spec (README.md, "Deformation specs"): a JSON description of a motor-handle
// deformation — method, handles, keys, options — parsed into a DeformSpec, bound once to one
// mesh of a model (the harmonic solve and the blend weights: paper sections III.A, IV, VIII) and
// applied per frame to any keys (eq. 2). The CLI, viewers and bindings share this one
// implementation, so its errors name the spec's fields (`spec.keys[1].rotate: ...`).
//
// Coordinates: a spec acts in mesh space (the positions as stored) or in world space (the bind
// pose that `cgamesh info` prints: each vertex skinned by its joints' bind matrices, a static
// mesh placed by its node). Selections and key centres are read in that space.

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/deform/arap.hpp"
#include "cgamesh/deform/cage_coordinates.hpp"
#include "cgamesh/deform/fabrik.hpp"
#include "cgamesh/deform/ffd.hpp"
#include "cgamesh/deform/harmonic_field.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/deform/spline_deform.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/world_surface.hpp"

namespace cgamesh::deform {

enum class DeformMethod {
  spline,    ///< spline-aligned (III): two handles, the keys along the harmonic parameter
  harmonic,  ///< harmonic coordinates (IV): one key per handle
  ffd,       ///< free-form deformation (V): handles select lattice control points, one key each
  cage,      ///< harmonic cage coordinates (VI): handles select cage vertices, or a deformed cage
  arap,      ///< as-rigid-as-possible (VII): one key per handle moves its vertices, the rest follows
};

/// The methods by the names a spec gives them.
extern const std::map<std::string, DeformMethod> kDeformMethods;

/// The method's name in a spec ("spline", "harmonic", "ffd", "cage", "arap").
[[nodiscard]] const char* method_name(DeformMethod method) noexcept;

/// How an FFD or cage spec moves its lattice or cage (sections V, VI).
enum class FfdVariant {
  classic,  ///< each control point (cage vertex) moved by its key, eq. 6 (p = Σ λ c)
  motor,    ///< each control point (cage vertex) carries its key as a motor, blended by eqs. 7-8
};

/// The cage of a cage spec; paths are resolved against the spec file's directory.
struct CageSpec {
  std::filesystem::path cage;                        ///< the rest cage (OBJ), in the spec's space
  std::optional<std::filesystem::path> deformed;     ///< classic: the posed cage, same vertices and faces
  int resolution = 64;                               ///< CageOptions::resolution
  std::optional<std::filesystem::path> coordinates;  ///< .npy cache: loaded if present, else computed and written
  int max_weights = 16;                              ///< CageSparsity::max_weights
};

/// The lattice of an FFD spec; its box is resolved against the mesh at bind.
struct LatticeSpec {
  std::array<int, 3> resolution{2, 2, 2};  ///< control points per axis, each in [2, kMaxLatticeResolution]
  LatticeBasis basis = LatticeBasis::bernstein;
  BsplineEnds ends = BsplineEnds::linear;
  std::optional<LatticeBox> box;  ///< unset: the mesh's bounding box grown by `margin`
  double margin = 0.01;           ///< × the bounding box diagonal, on every side; ≥ 0
};

enum class DeformSpace {
  mesh,   ///< the stored rest positions
  world,  ///< the bind pose in world space (what `cgamesh info` boxes)
};

/// What happens to a connected part of the mesh that holds no handle vertex (its harmonic
/// field would be undetermined).
enum class FreeParts {
  nearest,  ///< moves rigidly with the motor of the handle nearest to the part's centroid
  keep,     ///< stays in place
};

/// A handle's vertex set as the spec gives it; for the ffd method a set of lattice control points
/// (lattice_points, or the sphere or box containing their rest positions), for the cage method a
/// set of cage vertices (indices into the cage OBJ, or the sphere or box containing them at rest).
struct HandleSelection {
  enum class Kind { indices, sphere, box, lattice_points };
  Kind kind = Kind::indices;
  /// Kind::indices (≥ 0): mesh vertices as the file numbers them (Mesh::file_index; every vertex
  /// split from one), or by index for a mesh without the file's numbering; cage: cage vertices
  std::vector<int> indices;
  std::vector<std::array<int, 3>> points;  ///< Kind::lattice_points: control points [u, v, k] (ffd)
  std::array<double, 6> shape{};           ///< sphere: x, y, z, r; box: x0, y0, z0, x1, y1, z1
};

/// A key: x ↦ scale·R(axis, degrees)(x − center) + center + translate.
struct KeyTransform {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< non-zero
  double degrees = 0;
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double scale = 1;  ///< finite, > 0: a dilating versor (motor_blend.hpp)

  /// The key as the versor T(center + translate) D(scale) R T(−center).
  /// @throws InvalidInputError for a zero axis or a scale that is not finite and > 0.
  [[nodiscard]] cga::Versor<double> versor() const;
};

/// A FABRIK chain (III.C) whose solved joint motors become the keys.
struct IkChain {
  std::vector<Eigen::Vector3d> joints;  ///< #J rest joint positions
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
};

/// A parsed spec: every field typed and checked against itself (not yet against a mesh).
struct DeformSpec {
  DeformMethod method = DeformMethod::harmonic;
  int mesh = 0;                      ///< index of the model's mesh to deform
  std::optional<DeformSpace> space;  ///< unset: default_space() of the model
  LaplacianWeights weights = LaplacianWeights::mean_value;
  std::vector<HandleSelection> handles;
  std::vector<KeyTransform> keys;  ///< empty when `ik` is set
  std::optional<IkChain> ik;       ///< spline only
  SplineBasis basis = SplineBasis::bspline;
  int degree = 3;
  FreeParts free_parts = FreeParts::nearest;
  LatticeSpec lattice;                     ///< ffd only
  FfdVariant variant = FfdVariant::motor;  ///< ffd and cage
  CageSpec cage;                           ///< cage only
  /// arap only: energy, weights (cotangent unless the spec says clamped_cotangent), local step,
  /// iterations and tolerance; threads come from SpecBindOptions.
  ArapOptions arap;
};

/// Parses a spec from JSON text.
/// @param[in] text    the JSON document (an object)
/// @param[in] source  where it comes from (a path), for messages; a cage spec's files are
///                    relative to its directory
/// @throws InvalidInputError "spec SOURCE is not valid JSON: ...", "spec SOURCE: expected a JSON
///         object", or "spec.FIELD: ..." naming the first bad field (unknown field, bad value,
///         both keys and ik). Whether the method and basis take the number of keys is checked
///         by BoundDeformer, after the selections.
[[nodiscard]] DeformSpec parse_spec(std::string_view text, const std::string& source);

/// Reads and parses a spec file.
/// @param[in] path  the spec file
/// @throws FileError when it cannot be read or is a directory; InvalidInputError as parse_spec().
[[nodiscard]] DeformSpec read_spec(const std::filesystem::path& path);

/// The space a spec without "space" acts in: world when some mesh of the model is skinned
/// (boxes from `info` then select what the user sees), mesh otherwise.
[[nodiscard]] DeformSpace default_space(const anim::RiggedModel& model) noexcept;

/// Every mesh of a model as an OBJ or PLY holds it: positions and unit normals, per mesh.
/// Every mesh of `model` at rest in `space`: in mesh space its own positions and normals; in
/// world space the bind pose (matrix skinning, eq. 16; normals by each vertex's cofactor, as
/// anim::skin_normals()).
/// @throws InvalidInputError as anim::make_palette().
[[nodiscard]] mesh::WorldSurface rest_surfaces(const anim::RiggedModel& model, DeformSpace space);

/// rest_surfaces(model, space).positions.
/// @throws InvalidInputError as anim::make_palette().
[[nodiscard]] std::vector<mesh::RowMatrixXf<3>> rest_positions(const anim::RiggedModel& model, DeformSpace space);

struct SpecBindOptions {
  MotorBlendOptions blend;  ///< threads of apply()
};

/// A spec bound to one mesh of a model: the selections resolved, the harmonic field solved and
/// the blend weights built once (ffd: the lattice weights); apply() then costs one blend per
/// vertex (eq. 2; ffd: eq. 6 or 7), for the spec's keys or any others.
class BoundDeformer {
 public:
  /// Binds `spec` to mesh `spec.mesh` of `model` (sections III.A, IV). Connected parts without a
  /// handle vertex (parts as the harmonic field sees them: welded positions joined by a
  /// non-degenerate triangle) are moved as `spec.free_parts` says.
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
  [[nodiscard]] const std::vector<cga::Versor<double>>& keys() const noexcept { return keys_; }
  /// The FABRIK solution when the spec has an IK chain.
  [[nodiscard]] const std::optional<FabrikResult>& ik() const noexcept { return ik_; }
  /// #V×3 rest positions of the mesh in space() (what apply() deforms and handles select).
  [[nodiscard]] const mesh::RowMatrixXf<3>& rest_positions() const noexcept { return rest_; }
  /// Per handle, its vertex indices in the mesh (sorted for boxes and spheres, as given for
  /// index lists): what a viewer draws, at rest_positions() or at the apply() result.
  [[nodiscard]] const std::vector<std::vector<int>>& handles() const noexcept { return handles_; }
  /// Vertices of the parts that hold no handle vertex, ascending (ffd: outside the lattice box).
  [[nodiscard]] const std::vector<int>& free_vertices() const noexcept { return free_; }
  /// The bound lattice (ffd), else null.
  [[nodiscard]] const FreeFormDeformation* ffd() const noexcept { return ffd_ ? &*ffd_ : nullptr; }
  /// The bound cage (cage), else null.
  [[nodiscard]] const CageDeformation* cage() const noexcept { return cage_ ? &*cage_ : nullptr; }
  /// Per handle, its control point indices (Lattice::index()) for ffd, its cage vertices for cage;
  /// empty otherwise. Such a handle selects no mesh vertex: handles() then holds an empty set per
  /// handle.
  [[nodiscard]] const std::vector<std::vector<int>>& control_handles() const noexcept { return control_handles_; }
  /// ffd: the lattice's edges (neighbours along an axis); cage: the cage's edges; as pairs of
  /// control point indices, each once; empty otherwise. What a viewer draws between control_points().
  [[nodiscard]] const std::vector<std::array<int, 2>>& control_edges() const noexcept { return control_edges_; }
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
  void bind_ffd(const DeformSpec& spec, const SpecBindOptions& options);
  void bind_arap(const DeformSpec& spec, const mesh::Mesh& shape, const std::vector<std::vector<int>>& handles,
                 const SpecBindOptions& options);
  void apply_arap(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out, ArapReport* report) const;
  void bind_cage(const DeformSpec& spec, const mesh::Mesh& target, const SpecBindOptions& options);

  int mesh_ = 0;
  DeformSpace space_ = DeformSpace::mesh;
  std::vector<cga::Versor<double>> keys_;
  std::optional<FabrikResult> ik_;
  mesh::RowMatrixXf<3> rest_;
  std::vector<std::vector<int>> handles_;
  std::vector<int> free_;
  /// Per free vertex, the key that moves it, or −1 (kept).
  std::vector<int> free_key_;
  /// Mesh vertex of each vertex the blend deforms; empty when it deforms them all.
  std::vector<int> blended_;
  std::optional<MotorBlend> blend_;
  std::optional<ArapData> arap_;
  /// arap: every handle vertex of the deformed (sub-)mesh, handle after handle, and its key.
  std::vector<int> arap_handles_, arap_key_;
  /// arap: rest positions of arap_handles_ (in space()).
  Eigen::MatrixXd arap_rest_;
  std::optional<FreeFormDeformation> ffd_;
  FfdVariant variant_ = FfdVariant::motor;
  std::optional<CageDeformation> cage_;
  /// cage: the cage vertices before the keys (the deformed cage for classic, else the rest cage).
  std::vector<Eigen::Vector3d> cage_points_;
  std::vector<std::vector<int>> control_handles_;
  std::vector<std::array<int, 2>> control_edges_;
  /// ffd, cage: per control point (cage vertex), the handles that select it, ascending.
  std::vector<std::vector<int>> keys_of_point_;
  /// World space: #V inverse bind maps [A⁻¹  −A⁻¹ b].
  std::vector<Eigen::Matrix<double, 3, 4>> to_mesh_;
};

}  // namespace cgamesh::deform
