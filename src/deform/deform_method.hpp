#pragma once
// What each deformation method gives the spec (spec.hpp, bound_deformer.hpp): a parser of its own
// fields and a binder, registered once in deform_method.cpp; and the helpers every method's
// parser and binder share (JSON fields, the reach rule, selections, keys). A new method adds its
// file, its MethodSpec alternative and one registry entry.

#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/deform/spec.hpp"

namespace cgamesh::deform::detail {

using Json = nlohmann::json;

/// @throws InvalidInputError "spec.FIELD: WHAT".
[[noreturn]] void bad(const std::string& field, const std::string& what);

/// Exactly `count` finite numbers.
[[nodiscard]] std::vector<double> numbers(const Json& j, std::size_t count, const std::string& field);
[[nodiscard]] Eigen::Vector3d vector3(const Json& j, const std::string& field);
/// "rotate": [ax, ay, az, degrees] as an axis (non-zero) and an angle.
[[nodiscard]] std::pair<Eigen::Vector3d, double> parse_rotate(const Json& j, const std::string& field);
/// spec[field] as an integer, or `fallback` when absent.
[[nodiscard]] int integer(const Json& spec, const std::string& field, int fallback);
/// A file name field, relative to `base` (the spec's directory) unless absolute.
[[nodiscard]] std::filesystem::path file_field(const Json& j, const std::string& field,
                                               const std::filesystem::path& base);
/// Refuses a field of `j` not in `names`; `prefix` names the object in messages ("lattice.").
void only_fields(const Json& j, const std::vector<std::string>& names, const std::string& prefix);

/// The named value of spec[field], or `fallback` when absent; `prefix` names the object in
/// messages ("lattice.").
template <class E>
[[nodiscard]] E choice(const Json& spec, const std::string& field, const std::map<std::string, E>& names, E fallback,
                       const std::string& prefix = "") {
  if (!spec.contains(field)) return fallback;
  const Json& j = spec[field];
  if (j.is_string()) {
    const auto it = names.find(j.get<std::string>());
    if (it != names.end()) return it->second;
  }
  std::string list;
  for (const auto& [name, value] : names) list += (list.empty() ? "" : ", ") + name;
  bad(prefix + field, "expected one of " + list);
}

/// "free_parts" of the methods whose handles select mesh vertices.
[[nodiscard]] FreeParts parse_free_parts(const Json& j);
/// "handles" (required) into s.handles, by s's method (its fields already parsed: an ffd handle
/// reads the lattice's resolution).
void parse_handles(const Json& j, DeformSpec& s);
/// "keys" (required) into s.keys.
void parse_keys(const Json& j, DeformSpec& s);

/// The one rule for every point and length a spec gives, as for joint edits and tools: within
/// io::kMaxReach sizes of the deformed mesh (its box in the spec's space). Beyond, a value makes
/// no geometric sense for the model, and its arithmetic loses every digit of the model's
/// coordinates.
class Reach {
 public:
  /// @param[in] rest  #V×3 the mesh's rest positions in the spec's space
  explicit Reach(const mesh::RowMatrixXf<3>& rest);
  /// @throws InvalidInputError "spec.FIELD: ..." when `p` lies farther than the reach from the box.
  void point(const Eigen::Vector3d& p, const std::string& field) const;
  /// @throws InvalidInputError "spec.FIELD: ..." when `length` exceeds the reach.
  void length(double length, const std::string& field) const;
  void vector(const Eigen::Vector3d& v, const std::string& field) const { length(v.stableNorm(), field); }
  /// The diagonal of the mesh's box.
  [[nodiscard]] double size() const { return (hi_ - lo_).norm(); }

 private:
  [[noreturn]] void too_far(const std::string& field, const std::string& what) const;

  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();
  double reach_ = INFINITY;
};

/// What a binder reads.
struct BindInput {
  const DeformSpec& spec;
  const mesh::Mesh& target;          ///< the mesh as loaded
  const mesh::RowMatrixXf<3>& rest;  ///< #V×3 its rest positions in the spec's space
  const Reach& reach;
  const SpecBindOptions& options;
};

/// One method: its name in a spec, its own top-level fields, its parser and its binder.
struct DeformMethodEntry {
  const char* name;
  std::vector<std::string> fields;
  /// Parses the method's fields into s.fields, then the handles and keys (parse_handles,
  /// parse_keys) as the method takes them; `base` is the spec's directory.
  void (*parse)(const Json& j, DeformSpec& s, const std::filesystem::path& base);
  /// Binds in.spec (whose fields are this method's) to in.target; fills `out`.
  std::unique_ptr<BoundMethod> (*bind)(const BindInput& in, BoundHandles& out);
};

/// Every method, indexed by DeformMethod.
[[nodiscard]] const std::array<DeformMethodEntry, 5>& deform_methods();

/// A mesh's vertices by the file's numbering (Mesh::file_index), sorted once per bind.
class FileNumbering {
 public:
  explicit FileNumbering(const mesh::Mesh& m);
  /// The vertices an index list of file vertices names: in the order given, each file vertex's
  /// copies (split at seams) in ascending order.
  /// @throws InvalidInputError "spec.FIELD: ..." for an index the mesh does not hold.
  [[nodiscard]] std::vector<int> vertices(const std::vector<int>& indices, const std::string& field) const;

 private:
  std::vector<std::pair<int, int>> by_file_;  ///< (file vertex, vertex)
};

/// The vertices a selection picks from `positions` (#V×3, in the spec's space); index lists by
/// `numbering` when given, else as indices into `positions`. `noun` names what the positions are
/// in messages.
[[nodiscard]] std::vector<int> select(const HandleSelection& h, const mesh::RowMatrixXf<3>& positions,
                                      const std::string& field, const std::string& noun = "vertex",
                                      const FileNumbering* numbering = nullptr);

/// The spec's key transforms as versors.
[[nodiscard]] std::vector<cga::Versor<double>> key_versors(const DeformSpec& s);
/// @throws InvalidInputError "spec.keys: ..." unless the spec has one key per handle.
void check_one_key_per_handle(const DeformSpec& s);

/// Per point of `count`, the handles that select it, ascending.
[[nodiscard]] std::vector<std::vector<int>> keys_of_points(const std::vector<std::vector<int>>& handles,
                                                           Eigen::Index count);

}  // namespace cgamesh::deform::detail
