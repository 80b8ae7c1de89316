#include "cgamesh/deform/harmonic_field.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/union_find.hpp"
#include "cgamesh/mesh/weld.hpp"

namespace cgamesh::deform {

const std::map<std::string, LaplacianWeights> kLaplacianWeights{{"mean_value", LaplacianWeights::mean_value},
                                                                {"cotangent", LaplacianWeights::cotangent},
                                                                {"clamped_cotangent", LaplacianWeights::clamped_cotangent}};

using SparseMatrix = Eigen::SparseMatrix<double>;

namespace {

/// Calls visit(nodes, positions) for each face of `mesh` whose corners are three distinct nodes
/// and whose area is not zero: the triangles that carry Laplacian weights.
template <class Visit>
void for_each_weighted_triangle(const mesh::Mesh& mesh, std::span<const int> node, Visit&& visit) {
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    std::array<int, 3> v{}, n{};
    for (int c = 0; c < 3; ++c) {
      v[c] = mesh.faces(f, c);
      if (v[c] < 0 || v[c] >= mesh.vertex_count())
        throw InvalidInputError("harmonic field: face " + std::to_string(f) + " names vertex " + std::to_string(v[c]) +
                                " outside [0, " + std::to_string(mesh.vertex_count()) + ")");
      n[c] = node[static_cast<std::size_t>(v[c])];
    }
    if (n[0] == n[1] || n[1] == n[2] || n[0] == n[2]) continue;
    std::array<Eigen::Vector3d, 3> p;
    for (int c = 0; c < 3; ++c) p[c] = mesh.positions.row(v[c]).transpose().cast<double>();
    // Zero area: every angle is 0 or pi, and tan(pi/2) is infinite.
    if (!((p[1] - p[0]).cross(p[2] - p[0]).norm() > 0)) continue;
    visit(n, p);
  }
}

/// Half the cotangent of the angle at each corner (the weight of the opposite edge).
std::array<double, 3> half_cotangents(const std::array<Eigen::Vector3d, 3>& p, bool clamped) {
  std::array<double, 3> out{};
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d a = p[(c + 1) % 3] - p[c], b = p[(c + 2) % 3] - p[c];
    out[c] = 0.5 * a.dot(b) / a.cross(b).norm();
    if (clamped) out[c] = std::max(out[c], 0.0);
  }
  return out;
}

}  // namespace

std::vector<CotangentTriangle> cotangent_triangles(const mesh::Mesh& mesh, std::span<const int> node, bool clamped) {
  std::vector<CotangentTriangle> out;
  out.reserve(static_cast<std::size_t>(mesh.face_count()));
  for_each_weighted_triangle(mesh, node, [&](const std::array<int, 3>& n, const std::array<Eigen::Vector3d, 3>& p) {
    out.push_back({n, half_cotangents(p, clamped)});
  });
  return out;
}

SparseMatrix laplacian_edge_weights(const mesh::Mesh& mesh, std::span<const int> node, int node_count,
                                    LaplacianWeights weights) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.face_count()) * 12);
  const auto add = [&](int i, int j, double w) {
    triplets.emplace_back(i, j, w);
    triplets.emplace_back(j, i, w);
  };
  for_each_weighted_triangle(mesh, node, [&](const std::array<int, 3>& n, const std::array<Eigen::Vector3d, 3>& p) {
    if (weights != LaplacianWeights::mean_value) {
      const std::array<double, 3> w = half_cotangents(p, weights == LaplacianWeights::clamped_cotangent);
      for (int c = 0; c < 3; ++c) add(n[(c + 1) % 3], n[(c + 2) % 3], w[c]);
      return;
    }
    for (int c = 0; c < 3; ++c) {
      const int j = (c + 1) % 3, k = (c + 2) % 3;
      const Eigen::Vector3d a = p[j] - p[c], b = p[k] - p[c];
      // tan(theta/2) = |a x b| / (|a||b| + a.b); each direction counts half (symmetrised).
      const double half_tan = a.cross(b).norm() / (a.norm() * b.norm() + a.dot(b));
      add(n[c], n[j], 0.5 * half_tan / a.norm());
      add(n[c], n[k], 0.5 * half_tan / b.norm());
    }
  });
  SparseMatrix w(node_count, node_count);
  w.setFromTriplets(triplets.begin(), triplets.end());
  return w;
}

HarmonicPrecomputation harmonic_precompute(const mesh::Mesh& mesh, std::span<const int> constrained,
                                           const HarmonicOptions& options) {
  if (constrained.empty())
    throw InvalidInputError("harmonic field: the constraint set is empty; constrain at least one vertex per part");
  HarmonicPrecomputation pre;
  const Eigen::Index vertex_count = mesh.vertex_count();
  for (const int v : constrained)
    if (v < 0 || v >= vertex_count)
      throw InvalidInputError("harmonic field: constrained vertex " + std::to_string(v) + " is outside [0, " +
                              std::to_string(vertex_count) + ")");
  pre.node_of_vertex = mesh::weld_by_position(mesh.positions);
  const int node_count = mesh::number_classes(pre.node_of_vertex);
  pre.constrained.assign(constrained.begin(), constrained.end());
  const SparseMatrix w = laplacian_edge_weights(mesh, pre.node_of_vertex, node_count, options.weights);
  // Connected parts: nodes joined by an edge of non-zero weight.
  mesh::UnionFind parts(static_cast<std::size_t>(node_count));
  for (int col = 0; col < w.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(w, col); it; ++it) parts.unite(static_cast<int>(it.row()), col);

  // Constrained nodes get slots -1, -2, ...; the others free indices 0, 1, ...
  std::vector<int>& slot = pre.slot_of_node;
  slot.assign(static_cast<std::size_t>(node_count), 0);
  std::vector<char> component_constrained(static_cast<std::size_t>(node_count), 0);
  for (const int v : constrained) {
    const int n = pre.node_of_vertex[static_cast<std::size_t>(v)];
    if (slot[static_cast<std::size_t>(n)] == 0) slot[static_cast<std::size_t>(n)] = -1 - pre.constrained_nodes++;
    component_constrained[static_cast<std::size_t>(parts.find(n))] = 1;
  }
  int free_count = 0;
  for (int n = 0; n < node_count; ++n) {
    if (slot[static_cast<std::size_t>(n)] < 0) continue;
    if (!component_constrained[static_cast<std::size_t>(parts.find(n))]) {
      const auto it = std::find(pre.node_of_vertex.begin(), pre.node_of_vertex.end(), n);
      throw InvalidInputError("harmonic field: the connected part of the mesh containing vertex " +
                              std::to_string(it - pre.node_of_vertex.begin()) +
                              " has no constrained vertex; its field is undetermined (constrain a vertex of "
                              "every part, or remove unreferenced vertices)");
    }
    slot[static_cast<std::size_t>(n)] = free_count++;
  }

  // L = D - W; the free rows solve L_ff x_f = W_fc x_c.
  std::vector<Eigen::Triplet<double>> ff, fc;
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(free_count);
  for (int col = 0; col < w.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(w, col); it; ++it) {
      const int si = slot[static_cast<std::size_t>(it.row())], sj = slot[static_cast<std::size_t>(col)];
      if (si < 0 || it.row() == col) continue;
      diagonal[si] += it.value();
      if (sj >= 0)
        ff.emplace_back(si, sj, -it.value());
      else
        fc.emplace_back(si, -1 - sj, it.value());
    }
  for (int i = 0; i < free_count; ++i) ff.emplace_back(i, i, diagonal[i]);
  SparseMatrix lff(free_count, free_count);
  lff.setFromTriplets(ff.begin(), ff.end());
  pre.free_by_constrained.resize(free_count, pre.constrained_nodes);
  pre.free_by_constrained.setFromTriplets(fc.begin(), fc.end());
  if (free_count > 0) {
    pre.ldlt = std::make_unique<Eigen::SimplicialLDLT<SparseMatrix>>(lff);
    if (pre.ldlt->info() != Eigen::Success)
      throw SolverError(
          "harmonic field: the factorisation of the Laplacian failed (degenerate triangles, or "
          "cotangent weights on a mesh with very obtuse triangles: try mean-value weights)");
  }
  return pre;
}

Eigen::MatrixXd constrained_node_values(const HarmonicPrecomputation& pre, const Eigen::MatrixXd& boundary) {
  if (boundary.rows() != pre.constrained_count())
    throw InvalidInputError(std::to_string(boundary.rows()) + " rows of boundary values for " +
                            std::to_string(pre.constrained_count()) + " constrained vertices");
  if (!boundary.allFinite()) throw InvalidInputError("a boundary value is NaN or infinite");
  Eigen::MatrixXd xc(pre.constrained_nodes, boundary.cols());
  std::vector<int> row_of_slot(static_cast<std::size_t>(pre.constrained_nodes), -1);
  for (std::size_t r = 0; r < pre.constrained.size(); ++r) {
    const int v = pre.constrained[r];
    const int c = -1 - pre.slot_of_node[static_cast<std::size_t>(pre.node_of_vertex[static_cast<std::size_t>(v)])];
    int& first = row_of_slot[static_cast<std::size_t>(c)];
    if (first < 0) {
      first = static_cast<int>(r);
      xc.row(c) = boundary.row(static_cast<Eigen::Index>(r));
    } else if (xc.row(c) != boundary.row(static_cast<Eigen::Index>(r))) {
      throw InvalidInputError("vertex " + std::to_string(v) + " gets a value different from vertex " +
                              std::to_string(pre.constrained[static_cast<std::size_t>(first)]) +
                              " at the same position (or listed twice)");
    }
  }
  return xc;
}

Eigen::MatrixXd harmonic_solve(const HarmonicPrecomputation& pre, const Eigen::MatrixXd& boundary) {
  Eigen::MatrixXd xc;
  try {
    xc = constrained_node_values(pre, boundary);
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(std::string("harmonic_solve: ") + e.what());
  }
  Eigen::MatrixXd xf;
  if (pre.free_by_constrained.rows() > 0) {
    xf = pre.ldlt->solve(Eigen::MatrixXd(pre.free_by_constrained * xc));
    if (pre.ldlt->info() != Eigen::Success || !xf.allFinite())
      throw SolverError("harmonic_solve: the solve failed (non-finite result)");
  }
  Eigen::MatrixXd out(pre.vertex_count(), boundary.cols());
  for (Eigen::Index v = 0; v < out.rows(); ++v) {
    const int s = pre.slot_of_node[static_cast<std::size_t>(pre.node_of_vertex[static_cast<std::size_t>(v)])];
    out.row(v) = s >= 0 ? xf.row(s) : xc.row(-1 - s);
  }
  return out;
}

}  // namespace cgamesh::deform
