// The cage method (paper section VI): handles select cage vertices, one key each, or a deformed
// cage gives the pose; the mesh follows its harmonic cage coordinates (classic or motor).

#include <memory>
#include <optional>

#include "cgamesh/errors.hpp"
#include "control_point_method.hpp"

namespace cgamesh::deform::detail {
namespace {

void parse(const Json& j, DeformSpec& s, const std::filesystem::path& base) {
  CageSpec& c = s.fields.emplace<CageSpec>();
  c.variant = parse_variant(j);
  if (!j.contains("cage")) bad("cage", "missing (the cage OBJ)");
  c.cage = file_field(j, "cage", base);
  if (j.contains("deformed_cage")) {
    if (c.variant != FfdVariant::classic) bad("deformed_cage", "only the classic variant takes a deformed cage");
    c.deformed = file_field(j, "deformed_cage", base);
  }
  if (j.contains("coordinates")) c.coordinates = file_field(j, "coordinates", base);
  c.resolution = integer(j, "resolution", c.resolution);
  if (c.resolution < kMinCageResolution || c.resolution > kMaxCageResolution)
    bad("resolution", "expected an integer in [" + std::to_string(kMinCageResolution) + ", " +
                          std::to_string(kMaxCageResolution) + "]");
  c.max_weights = integer(j, "max_weights", c.max_weights);
  if (c.max_weights < 1) bad("max_weights", "expected an integer >= 1");
  if (c.deformed) {
    // The deformed cage is the pose: no handles or keys to combine with it.
    for (const char* field : {"handles", "keys"})
      if (j.contains(field)) bad(field, "a spec with a deformed_cage takes no handles or keys");
    return;
  }
  parse_handles(j, s);
  parse_keys(j, s);
}

/// The mesh's cage coordinates: from the cache when it exists, else solved (and cached).
Eigen::MatrixXd coordinates_of(const CageSpec& c, const BindInput& in, const Cage& cage) {
  Eigen::MatrixXd coordinates;
  try {
    if (c.coordinates && std::filesystem::exists(*c.coordinates)) {
      check_cage(cage);
      coordinates = load_cage_coordinates(*c.coordinates, in.rest.rows(), cage.vertices.rows());
    } else {
      CageOptions solve;
      solve.resolution = c.resolution;
      solve.threads = in.options.blend.threads;
      solve.vertex_labels =
          std::span(in.target.file_index.data(), static_cast<std::size_t>(in.target.file_index.size()));
      coordinates = cage_coordinates(in.rest, cage, solve);
    }
  } catch (const FileError&) {
    rethrow_with_context("spec.coordinates: ");
  } catch (const TopologyError& e) {
    bad("cage", e.what());  // a bad value of the field, as the CLI reports it (exit 2)
  } catch (const Error&) {
    rethrow_with_context("spec.cage: ");
  }
  if (c.coordinates && !std::filesystem::exists(*c.coordinates)) {
    try {
      save_cage_coordinates(*c.coordinates, coordinates);
    } catch (const Error&) {
      rethrow_with_context("spec.coordinates: ");
    }
  }
  return coordinates;
}

class CageMethod final : public ControlPointMethod<CageDeformation> {
 public:
  using ControlPointMethod::ControlPointMethod;
  [[nodiscard]] const CageDeformation* cage() const noexcept override { return &deformer_; }
};

std::unique_ptr<BoundMethod> bind(const BindInput& in, BoundHandles& out) {
  const auto& c = std::get<CageSpec>(in.spec.fields);
  Cage cage = read_cage_obj(c.cage);
  CageSparsity sparsity;
  sparsity.max_weights = c.max_weights;
  CageDeformation deformer(in.rest, cage, coordinates_of(c, in, cage), sparsity, in.options.blend.threads);
  if (c.deformed) {
    const Cage posed = read_cage_obj(*c.deformed);
    if (posed.vertices.rows() != cage.vertices.rows() || posed.faces != cage.faces)
      bad("deformed_cage", "has other vertices or faces than the cage (" + std::to_string(posed.vertices.rows()) +
                               " vertices and " + std::to_string(posed.faces.rows()) + " faces for " +
                               std::to_string(cage.vertices.rows()) + " and " + std::to_string(cage.faces.rows()) +
                               ")");
    cage = posed;
  }
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index v = 0; v < cage.vertices.rows(); ++v) points.push_back(cage.vertices.row(v).transpose());
  const mesh::RowMatrixXf<3> at_rest = deformer.cage_vertices().cast<float>();
  for (std::size_t h = 0; h < in.spec.handles.size(); ++h)
    out.control_handles.push_back(
        select(in.spec.handles[h], at_rest, "handles[" + std::to_string(h) + "]", "cage vertex"));
  out.handles.resize(in.spec.handles.size());
  // A checked cage is closed and consistently oriented: each edge runs once each way.
  for (Eigen::Index f = 0; f < cage.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (cage.faces(f, k) < cage.faces(f, (k + 1) % 3))
        out.control_edges.push_back({cage.faces(f, k), cage.faces(f, (k + 1) % 3)});
  check_one_key_per_handle(in.spec);
  out.keys = key_versors(in.spec);
  return std::make_unique<CageMethod>(std::move(deformer), c.variant,
                                      keys_of_points(out.control_handles, cage.vertices.rows()), std::move(points));
}

}  // namespace

DeformMethodEntry cage_method() {
  return {"cage", {"variant", "cage", "deformed_cage", "resolution", "coordinates", "max_weights"}, parse, bind};
}

}  // namespace cgamesh::deform::detail
