#include "vertex_handles.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/SparseCore>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/mesh/union_find.hpp"
#include "cgamesh/mesh/weld.hpp"

namespace cgamesh::deform::detail {
namespace {

/// Per vertex, its connected part as the harmonic field sees it (harmonic_precompute): welded
/// positions joined by an edge of non-zero weight; numbered by their smallest welded node.
std::vector<int> parts_of(const mesh::Mesh& shape, LaplacianWeights weights) {
  std::vector<int> node = mesh::weld_by_position(shape.positions);
  const int node_count = mesh::number_classes(node);
  const Eigen::SparseMatrix<double> w = laplacian_edge_weights(shape, node, node_count, weights);
  mesh::UnionFind parts(static_cast<std::size_t>(node_count));
  for (int col = 0; col < w.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, col); it; ++it) parts.unite(static_cast<int>(it.row()), col);
  for (int& n : node) n = parts.find(n);
  return node;
}

/// Per free vertex, the key that moves its part: that of the handle with the vertex nearest to
/// the part's centroid (spline ends: handle 0 is the first key, handle 1 the last), or −1 (keep).
std::vector<int> free_part_keys(FreeParts free_parts, bool spline_ends, const mesh::RowMatrixXf<3>& rest,
                                const std::vector<std::vector<int>>& handles, const std::vector<int>& free,
                                const std::vector<int>& part, std::size_t key_count) {
  if (free_parts == FreeParts::keep) return std::vector<int>(free.size(), -1);
  std::vector<Eigen::Vector3d> sum(part.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(part.size(), 0);
  for (const int v : free) {
    sum[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])] += rest.row(v).transpose().cast<double>();
    ++count[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])];
  }
  std::vector<int> key_of_part(part.size(), -1);
  for (std::size_t p = 0; p < part.size(); ++p) {
    if (count[p] == 0) continue;
    const Eigen::Vector3d centroid = sum[p] / count[p];
    double best = INFINITY;
    for (std::size_t h = 0; h < handles.size(); ++h)
      for (const int v : handles[h]) {
        const double d = (rest.row(v).transpose().cast<double>() - centroid).squaredNorm();
        if (d < best) {
          best = d;
          key_of_part[p] = spline_ends && h == 1 ? static_cast<int>(key_count) - 1 : static_cast<int>(h);
        }
      }
  }
  std::vector<int> out;
  for (const int v : free) out.push_back(key_of_part[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])]);
  return out;
}

}  // namespace

LaplacianWeights parse_field_weights(const Json& j) {
  return choice<LaplacianWeights>(
      j, "weights", {{"mean_value", LaplacianWeights::mean_value}, {"cotangent", LaplacianWeights::cotangent}},
      LaplacianWeights::mean_value);
}

std::vector<cga::Versor<double>> rest_keys(std::size_t count) {
  return std::vector<cga::Versor<double>>(count, cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>()));
}

void select_vertex_handles(const BindInput& in, BoundHandles& out) {
  std::vector<int> node = mesh::weld_by_position(in.rest);
  mesh::number_classes(node);
  std::vector<int> owner(static_cast<std::size_t>(in.rest.rows()), -1);  // handle of each welded node
  std::optional<FileNumbering> numbering;
  if (in.target.file_index.rows() > 0 &&
      std::any_of(in.spec.handles.begin(), in.spec.handles.end(),
                  [](const HandleSelection& h) { return h.kind == HandleSelection::Kind::indices; }))
    numbering.emplace(in.target);
  for (std::size_t h = 0; h < in.spec.handles.size(); ++h) {
    const std::string field = "handles[" + std::to_string(h) + "]";
    out.handles.push_back(select(in.spec.handles[h], in.rest, field, "vertex", numbering ? &*numbering : nullptr));
    for (const int v : out.handles.back()) {
      int& o = owner[static_cast<std::size_t>(node[static_cast<std::size_t>(v)])];
      if (o >= 0 && o != static_cast<int>(h))
        bad(field, "vertex " + std::to_string(in.target.vertex_label(v)) +
                       " (or a vertex at its position) is also in handles[" + std::to_string(o) +
                       "]; handles must be disjoint");
      o = static_cast<int>(h);
    }
  }
}

HandledShape split_free_parts(const BindInput& in, LaplacianWeights weights, FreeParts free_parts, bool spline_ends,
                              BoundHandles& out) {
  HandledShape s;
  s.shape.positions = in.rest;
  s.shape.faces = in.target.faces;
  s.handles = out.handles;
  const std::vector<int> part = parts_of(s.shape, weights);
  std::vector<char> handled(part.size(), 0);
  for (const auto& h : out.handles)
    for (const int v : h) handled[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])] = 1;
  if (std::all_of(part.begin(), part.end(), [&](int p) { return handled[static_cast<std::size_t>(p)] != 0; }))
    return s;
  std::vector<int> index(part.size(), -1);  // vertex -> its index in the handled sub-mesh
  for (std::size_t v = 0; v < part.size(); ++v) {
    if (handled[static_cast<std::size_t>(part[v])]) {
      index[v] = static_cast<int>(s.blended.size());
      s.blended.push_back(static_cast<int>(v));
    } else {
      out.free.push_back(static_cast<int>(v));
    }
  }
  for (auto& h : s.handles)
    for (int& v : h) v = index[static_cast<std::size_t>(v)];
  mesh::Mesh sub;
  sub.positions = in.rest(s.blended, Eigen::all);
  std::vector<int> faces;
  for (Eigen::Index f = 0; f < s.shape.faces.rows(); ++f) {
    // A face joins one part, or is degenerate (no edge of the field): then it is dropped.
    const std::array<int, 3> corner = {index[static_cast<std::size_t>(s.shape.faces(f, 0))],
                                       index[static_cast<std::size_t>(s.shape.faces(f, 1))],
                                       index[static_cast<std::size_t>(s.shape.faces(f, 2))]};
    if (std::all_of(corner.begin(), corner.end(), [](int c) { return c >= 0; }))
      faces.insert(faces.end(), corner.begin(), corner.end());
  }
  sub.faces = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      faces.data(), static_cast<Eigen::Index>(faces.size() / 3), 3);
  s.shape = std::move(sub);
  s.free_key = free_part_keys(free_parts, spline_ends, in.rest, out.handles, out.free, part, out.keys.size());
  return s;
}

VertexHandleMethod::VertexHandleMethod(const HandledShape& shape, const mesh::RowMatrixXf<3>& rest,
                                       std::vector<int> free)
    : rest_(shape.blended.empty() ? mesh::RowMatrixXf<3>() : rest),
      blended_(shape.blended),
      free_(std::move(free)),
      free_key_(shape.free_key) {}

void VertexHandleMethod::apply(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out,
                               ArapReport* report) const {
  if (blended_.empty()) {
    deform(keys, out, report);
    return;
  }
  mesh::RowMatrixXf<3> part;
  deform(keys, part, report);
  out = rest_;
  for (std::size_t v = 0; v < blended_.size(); ++v) out.row(blended_[v]) = part.row(static_cast<Eigen::Index>(v));
  // The rest keys are identities, so a handle's motor is its key applied to the rest shape.
  std::vector<std::optional<Eigen::Matrix<float, 3, 4>>> maps(keys.size());
  for (std::size_t f = 0; f < free_.size(); ++f) {
    const int k = free_key_[f];
    if (k < 0) continue;
    auto& map = maps[static_cast<std::size_t>(k)];
    if (!map) map = cga::PointMap<double>(keys[static_cast<std::size_t>(k)]).affine_matrix().cast<float>();
    const auto v = free_[f];
    out.row(v) = (map->leftCols<3>() * rest_.row(v).transpose() + map->col(3)).transpose();
  }
}

}  // namespace cgamesh::deform::detail
