// The arap method (paper section VII): each handle's vertices at its key applied to their rest
// positions, every other vertex by the as-rigid-as-possible solve from the rest shape.

#include <memory>

#include "cgamesh/cga/point_map.hpp"
#include "vertex_handles.hpp"

namespace cgamesh::deform::detail {
namespace {

/// More iterations than this are a typo, not a request (each costs a solve).
constexpr int kMaxArapIterations = 100000;

void parse(const Json& j, DeformSpec& s, const std::filesystem::path&) {
  ArapSpec& f = s.fields.emplace<ArapSpec>();
  ArapOptions& a = f.options;
  a.weights = choice<LaplacianWeights>(
      j, "weights",
      {{"cotangent", LaplacianWeights::cotangent}, {"clamped_cotangent", LaplacianWeights::clamped_cotangent}},
      LaplacianWeights::cotangent);
  a.energy = choice<ArapEnergy>(j, "energy",
                                {{"spokes", ArapEnergy::spokes}, {"spokes_and_rims", ArapEnergy::spokes_and_rims}},
                                ArapEnergy::spokes_and_rims);
  a.local_step = choice<ArapLocalStep>(j, "local_step", {{"rotor", ArapLocalStep::rotor}, {"svd", ArapLocalStep::svd}},
                                       ArapLocalStep::rotor);
  if (j.contains("iterations")) {
    const Json& n = j["iterations"];
    if (!n.is_number_integer() || n.get<long long>() < 1 || n.get<long long>() > kMaxArapIterations)
      bad("iterations", "expected an integer in [1, " + std::to_string(kMaxArapIterations) + "]");
    a.iterations = n.get<int>();
  }
  if (j.contains("tolerance")) {
    const Json& t = j["tolerance"];
    if (!t.is_number() || !std::isfinite(t.get<double>()) || t.get<double>() < 0)
      bad("tolerance", "expected a finite number >= 0 (the relative energy decrease that stops the iterations)");
    a.tolerance = t.get<double>();
  }
  f.free_parts = parse_free_parts(j);
  parse_handles(j, s);
  parse_keys(j, s);
}

/// Every handle vertex of the handled shape, handle after handle, and its key.
struct ArapHandles {
  std::vector<int> vertices, key;

  explicit ArapHandles(const std::vector<std::vector<int>>& handles) {
    for (std::size_t h = 0; h < handles.size(); ++h)
      for (const int v : handles[h]) {
        vertices.push_back(v);
        key.push_back(static_cast<int>(h));
      }
  }
};

class ArapMethod final : public VertexHandleMethod {
 public:
  ArapMethod(const HandledShape& shape, const BindInput& in, const BoundHandles& out, ArapOptions options)
      : VertexHandleMethod(shape, in.rest, out.free),
        handles_(shape.handles),
        rest_(shape.shape.positions(handles_.vertices, Eigen::all).cast<double>()),
        data_(arap_precompute(shape.shape, handles_.vertices, with_threads(options, in.options.blend.threads))) {}

 private:
  static ArapOptions with_threads(ArapOptions options, int threads) {
    options.threads = threads;
    return options;
  }

  void deform(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out,
              ArapReport* report) const override {
    (void)similarity_logs(keys);  // each key a similarity, as the blend requires
    std::vector<Eigen::Matrix<double, 3, 4>> maps;
    for (const auto& k : keys) maps.push_back(cga::PointMap<double>(k).affine_matrix());
    Eigen::MatrixXd targets(rest_.rows(), 3);
    for (Eigen::Index i = 0; i < targets.rows(); ++i) {
      const Eigen::Matrix<double, 3, 4>& m = maps[static_cast<std::size_t>(handles_.key[static_cast<std::size_t>(i)])];
      targets.row(i) = (m.leftCols<3>() * rest_.row(i).transpose() + m.col(3)).transpose();
    }
    Eigen::MatrixXd positions;
    const ArapReport r = arap_solve(data_, targets, positions);
    if (report != nullptr) *report = r;
    out = positions.cast<float>();
  }

  ArapHandles handles_;
  Eigen::MatrixXd rest_;  ///< #H×3 rest positions of handles_.vertices
  ArapData data_;
};

std::unique_ptr<BoundMethod> bind(const BindInput& in, BoundHandles& out) {
  const auto& f = std::get<ArapSpec>(in.spec.fields);
  select_vertex_handles(in, out);
  check_one_key_per_handle(in.spec);  // after the selections, so that a bad index is named first
  out.keys = key_versors(in.spec);
  const HandledShape shape = split_free_parts(in, f.options.weights, f.free_parts, false, out);
  return std::make_unique<ArapMethod>(shape, in, out, f.options);
}

}  // namespace

DeformMethodEntry arap_method() {
  return {"arap", {"weights", "free_parts", "energy", "local_step", "iterations", "tolerance"}, parse, bind};
}

}  // namespace cgamesh::deform::detail
