#pragma once
// The deformation spec (README.md, "Deformation specs"): a JSON description of a motor-handle
// deformation — method, handles, keys, options — parsed into a DeformSpec; bound_deformer.hpp
// binds it to one mesh of a model and applies it per frame. The CLI, viewers and bindings share
// this one implementation, so its errors name the spec's fields (`spec.keys[1].rotate: ...`).
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
#include <type_traits>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/deform/arap.hpp"
#include "cgamesh/deform/ffd.hpp"
#include "cgamesh/deform/harmonic_field.hpp"
#include "cgamesh/deform/spline_deform.hpp"

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
  FfdVariant variant = FfdVariant::motor;
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

/// The fields of the harmonic method (IV).
struct HarmonicSpec {
  LaplacianWeights weights = LaplacianWeights::mean_value;
  FreeParts free_parts = FreeParts::nearest;
};

/// The fields of the spline method (III): the harmonic parameter's field, the spline, and either
/// the spec's keys or an IK chain whose motors become the keys.
struct SplineSpec {
  LaplacianWeights weights = LaplacianWeights::mean_value;
  FreeParts free_parts = FreeParts::nearest;
  SplineBasis basis = SplineBasis::bspline;
  int degree = 3;
  std::optional<IkChain> ik;
};

/// The fields of the ffd method (V).
struct FfdSpec {
  LatticeSpec lattice;
  FfdVariant variant = FfdVariant::motor;
};

/// The fields of the arap method (VII): energy, weights (cotangent unless the spec says
/// clamped_cotangent), local step, iterations and tolerance; threads come from SpecBindOptions.
struct ArapSpec {
  ArapOptions options;
  FreeParts free_parts = FreeParts::nearest;
};

/// One method's own fields; the alternative's index is its DeformMethod.
using MethodSpec = std::variant<SplineSpec, HarmonicSpec, FfdSpec, CageSpec, ArapSpec>;
static_assert(std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(DeformMethod::spline), MethodSpec>,
                             SplineSpec> &&
              std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(DeformMethod::harmonic), MethodSpec>,
                             HarmonicSpec> &&
              std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(DeformMethod::ffd), MethodSpec>,
                             FfdSpec> &&
              std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(DeformMethod::cage), MethodSpec>,
                             CageSpec> &&
              std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(DeformMethod::arap), MethodSpec>,
                             ArapSpec>);

/// A parsed spec: every field typed and checked against itself (not yet against a mesh): the
/// fields every method shares, and the method's own.
struct DeformSpec {
  int mesh = 0;                      ///< index of the model's mesh to deform
  std::optional<DeformSpace> space;  ///< unset: default_space() of the model
  std::vector<HandleSelection> handles;
  std::vector<KeyTransform> keys;  ///< empty when the spline's `ik` is set, or with a deformed cage
  MethodSpec fields = HarmonicSpec{};

  [[nodiscard]] DeformMethod method() const noexcept { return static_cast<DeformMethod>(fields.index()); }
  /// How the parts without a handle vertex move (spline, harmonic, arap); unset for ffd and cage,
  /// whose handles select control points.
  [[nodiscard]] std::optional<FreeParts> free_parts() const noexcept {
    return std::visit(
        [](const auto& f) -> std::optional<FreeParts> {
          if constexpr (requires { f.free_parts; })
            return f.free_parts;
          else
            return std::nullopt;
        },
        fields);
  }
};

/// Parses a spec from JSON text: the shared fields here, each method's own by its parser
/// (registered once per method, src/deform/deform_method.hpp).
/// @param[in] text    the JSON document (an object)
/// @param[in] source  where it comes from (a path), for messages; a cage spec's files are
///                    relative to its directory
/// @throws InvalidInputError "spec SOURCE is not valid JSON: ...", "spec SOURCE: expected a JSON
///         object", or "spec.FIELD: ..." naming the first bad field (unknown field, a field of
///         another method, bad value, both keys and ik). Whether the method and basis take the
///         number of keys is checked by BoundDeformer, after the selections.
[[nodiscard]] DeformSpec parse_spec(std::string_view text, const std::string& source);

/// Reads and parses a spec file.
/// @param[in] path  the spec file
/// @throws FileError when it cannot be read or is a directory; InvalidInputError as parse_spec().
[[nodiscard]] DeformSpec read_spec(const std::filesystem::path& path);

}  // namespace cgamesh::deform
