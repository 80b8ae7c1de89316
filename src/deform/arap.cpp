#include "cgamesh/deform/arap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <Eigen/SparseCore>

#include "cgamesh/cga/convert.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/weld.hpp"

#include "../parallel_for.hpp"

namespace cgamesh::detail {

/// One cell term: the edge (a, b) of welded nodes with weight w and w·(p_a − p_b) at rest.
struct ArapEdge {
  int a = 0, b = 0;
  double weight = 0;
  Eigen::Vector3d weighted_rest = Eigen::Vector3d::Zero();
};

/// One right-hand-side term of a node: R_cell · vector.
struct ArapRhsTerm {
  int cell = 0;
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();
};

}  // namespace cgamesh::detail

namespace cgamesh::deform {
namespace {

using detail::ArapEdge;
using detail::ArapRhsTerm;

using SparseMatrix = Eigen::SparseMatrix<double>;
using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// Horn's symmetric 4×4 matrix of S (section VII): its top eigenvector is the quaternion
/// (w, x, y, z) of the rotation maximising tr(R S).
Eigen::Matrix4d horn_matrix(const Eigen::Matrix3d& s) {
  Eigen::Matrix4d p;
  p << s(0, 0) + s(1, 1) + s(2, 2), s(1, 2) - s(2, 1), s(2, 0) - s(0, 2), s(0, 1) - s(1, 0),  //
      s(1, 2) - s(2, 1), s(0, 0) - s(1, 1) - s(2, 2), s(0, 1) + s(1, 0), s(2, 0) + s(0, 2),   //
      s(2, 0) - s(0, 2), s(0, 1) + s(1, 0), -s(0, 0) + s(1, 1) - s(2, 2), s(1, 2) + s(2, 1),  //
      s(0, 1) - s(1, 0), s(2, 0) + s(0, 2), s(1, 2) + s(2, 1), -s(0, 0) - s(1, 1) + s(2, 2);
  return p;
}

/// The determinant of the 3×3 minor of `a` without row r and column c.
double minor3(const Eigen::Matrix4d& a, int r, int c) {
  const int r0 = r == 0 ? 1 : 0, r1 = r <= 1 ? 2 : 1, r2 = r <= 2 ? 3 : 2;
  const int c0 = c == 0 ? 1 : 0, c1 = c <= 1 ? 2 : 1, c2 = c <= 2 ? 3 : 2;
  return a(r0, c0) * (a(r1, c1) * a(r2, c2) - a(r1, c2) * a(r2, c1)) -
         a(r0, c1) * (a(r1, c0) * a(r2, c2) - a(r1, c2) * a(r2, c0)) +
         a(r0, c2) * (a(r1, c0) * a(r2, c1) - a(r1, c1) * a(r2, c0));
}

/// The unit quaternion (w, x, y, z) of the top eigenvector of Horn's matrix. The largest root
/// of the characteristic quartic λ⁴ − 2‖S‖² λ² − 8 det(S) λ + det(P) (P is traceless and
/// ‖P‖² = 4‖S‖²) by Newton from the bound √3‖S‖ ≥ σ₁ + σ₂ + σ₃ ≥ λ_max, where the quartic is
/// convex and Newton descends monotonically; then the eigenvector as a column of the adjugate
/// of P − λI (rank 3). Cheaper than a 4×4 eigensolver, as accurate (tests compare
/// it with the SVD to 1e-9).
Eigen::Vector4d top_quaternion(const Eigen::Matrix3d& s) {
  const double norm2 = s.squaredNorm();
  if (!(norm2 > 0)) return {1, 0, 0, 0};
  const Eigen::Matrix4d p = horn_matrix(s);
  const double c2 = -2 * norm2, c1 = -8 * s.determinant(), c0 = p.determinant();
  double lambda = std::sqrt(3 * norm2);
  for (int k = 0; k < 50; ++k) {
    const double l2 = lambda * lambda;
    const double f = (l2 + c2) * l2 + c1 * lambda + c0, df = 4 * l2 * lambda + 2 * c2 * lambda + c1;
    if (!(df > 0)) break;
    const double step = f / df;
    lambda -= step;
    if (!(std::abs(step) > 1e-15 * std::abs(lambda))) break;
  }
  Eigen::Matrix4d a = p;
  a.diagonal().array() -= lambda;
  // adj(A) = Π_{k>1} (λ_k − λ) q qᵀ: its largest diagonal entry picks the column along q's
  // largest component, the best conditioned one (7 minors instead of 16).
  int column = 0;
  double largest = 0;
  for (int c = 0; c < 4; ++c) {
    const double d = std::abs(minor3(a, c, c));
    if (d > largest) largest = d, column = c;
  }
  Eigen::Vector4d best;
  for (int r = 0; r < 4; ++r) best[r] = ((r + column) % 2 == 0 ? 1 : -1) * minor3(a, column, r);
  // A repeated top eigenvalue (S of rank ≤ 1: collinear edges) leaves the adjugate ~0 and the
  // rotation undetermined; any eigenvector of the eigensolver is then as good.
  if (!(best.squaredNorm() > 1e-24 * norm2 * norm2 * norm2)) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(p);
    best = eigen.eigenvectors().col(3);
  }
  return best.normalized();
}

Eigen::Matrix3d rotation_from_quaternion(const Eigen::Vector4d& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
}

/// The cells of each triangle edge: its two ends (spokes) and the opposite corner (rims).
int cells_per_edge(ArapEnergy energy) { return energy == ArapEnergy::spokes ? 2 : 3; }

void check_options(const ArapOptions& options) {
  if (options.weights == LaplacianWeights::mean_value)
    throw InvalidInputError("arap: mean-value weights are not an ARAP energy (use cotangent or clamped_cotangent)");
  if (options.iterations < 1)
    throw InvalidInputError("arap: iterations must be >= 1, not " + std::to_string(options.iterations));
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance))
    throw InvalidInputError("arap: the tolerance must be a finite number >= 0");
}

/// Nodes of the smallest part worth a thread in the local step and the right-hand sides: a node
/// costs ≈ 0.3 µs (7 edges, Horn's rotor), ≈ 30 vertices of skinning, so the arm (8 002 nodes)
/// and the cow (2 903) split too.
constexpr Eigen::Index kMinArapPart = 512;

/// Each cell's covariance S = Σ w (p_a − p_b)_rest (p′_a − p′_b)ᵀ and rotation into rotations,
/// its energy E = Σ w‖d′‖² + Σ w‖d‖² − 2 tr(R S) into energies.
/// @param[in] edge_begin   #N+1: cell n holds edges[edge_begin[n], edge_begin[n+1])
/// @param[in] rest_energy  #N Σ w‖d‖² of each cell
/// @param[in] p            #N×3 deformed node positions
void local_step(std::span<const int> edge_begin, std::span<const ArapEdge> edges, std::span<const double> rest_energy,
                const ArapOptions& options, const Eigen::MatrixXd& p, std::vector<Eigen::Matrix3d>& rotations,
                std::vector<double>& energies) {
  detail::parallel_for(
      static_cast<Eigen::Index>(rest_energy.size()), options.threads,
      [&](Eigen::Index begin, Eigen::Index end) {
        for (Eigen::Index n = begin; n < end; ++n) {
          Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
          double deformed = 0;
          for (int e = edge_begin[static_cast<std::size_t>(n)]; e < edge_begin[static_cast<std::size_t>(n) + 1]; ++e) {
            const ArapEdge& edge = edges[static_cast<std::size_t>(e)];
            const Eigen::Vector3d d = (p.row(edge.a) - p.row(edge.b)).transpose();
            s.noalias() += edge.weighted_rest * d.transpose();
            deformed += edge.weight * d.squaredNorm();
          }
          Eigen::Matrix3d& r = rotations[static_cast<std::size_t>(n)];
          r = options.local_step == ArapLocalStep::rotor ? rotation_from_quaternion(top_quaternion(s))
                                                         : arap_rotation_svd(s);
          energies[static_cast<std::size_t>(n)] =
              deformed + rest_energy[static_cast<std::size_t>(n)] - 2 * (r.cwiseProduct(s.transpose())).sum();
        }
      },
      kMinArapPart);
}

}  // namespace

cga::Rotor<double> arap_rotor(const Eigen::Matrix3d& covariance) {
  const Eigen::Vector4d q = top_quaternion(covariance);
  return cga::rotor(Eigen::Quaterniond(q[0], q[1], q[2], q[3]));
}

Eigen::Matrix3d arap_rotation_svd(const Eigen::Matrix3d& covariance) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  // tr(R S) = tr(Σ Vᵀ R U) is largest for R = V Uᵀ; a reflection flips the smallest singular direction.
  if ((svd.matrixV() * u.transpose()).determinant() < 0) u.col(2) *= -1;
  return svd.matrixV() * u.transpose();
}

ArapData::ArapData() = default;
ArapData::ArapData(ArapData&& other) noexcept = default;
ArapData& ArapData::operator=(ArapData&& other) noexcept = default;
ArapData::~ArapData() = default;

ArapData arap_precompute(const mesh::Mesh& mesh, std::span<const int> handles, const ArapOptions& options) {
  check_options(options);
  ArapData data;
  data.options_ = options;
  HarmonicOptions harmonic;
  harmonic.weights = options.weights;
  try {
    data.system_ = harmonic_precompute(mesh, handles, harmonic);
  } catch (const SolverError& e) {
    throw SolverError(std::string("arap: ") + e.what());
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(std::string("arap: ") + e.what());
  }
  const std::vector<int>& node = data.system_.node_of_vertex;
  const int node_count = static_cast<int>(data.system_.slot_of_node.size());
  data.rest_.resize(node_count, 3);
  for (std::size_t v = 0; v < node.size(); ++v)
    data.rest_.row(node[v]) = mesh.positions.row(static_cast<Eigen::Index>(v)).cast<double>();

  // Undirected edges numbered by their place in a compressed pattern, so that the terms of a
  // cell merge by setFromTriplets (an edge is in a cell once per triangle that puts it there).
  const std::vector<CotangentTriangle> triangles =
      cotangent_triangles(mesh, node, options.weights == LaplacianWeights::clamped_cotangent);
  std::vector<Eigen::Triplet<double>> pattern;
  pattern.reserve(triangles.size() * 3);
  for (const CotangentTriangle& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const int j = t.node[static_cast<std::size_t>((c + 1) % 3)], k = t.node[static_cast<std::size_t>((c + 2) % 3)];
      pattern.emplace_back(std::min(j, k), std::max(j, k), 1.0);
    }
  SparseMatrix edge_id(node_count, node_count);
  edge_id.setFromTriplets(pattern.begin(), pattern.end());
  std::vector<std::array<int, 2>> edge_ends(static_cast<std::size_t>(edge_id.nonZeros()));
  for (int col = 0, id = 0; col < edge_id.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(edge_id, col); it; ++it, ++id) {
      it.valueRef() = id;
      edge_ends[static_cast<std::size_t>(id)] = {static_cast<int>(it.row()), col};
    }

  std::vector<Eigen::Triplet<double>> cell_terms;
  cell_terms.reserve(triangles.size() * 9);
  for (const CotangentTriangle& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const int j = t.node[static_cast<std::size_t>((c + 1) % 3)], k = t.node[static_cast<std::size_t>((c + 2) % 3)];
      const int id = static_cast<int>(edge_id.coeff(std::min(j, k), std::max(j, k)));
      const double w = t.half_cot[static_cast<std::size_t>(c)];
      cell_terms.emplace_back(j, id, w);
      cell_terms.emplace_back(k, id, w);
      if (options.energy == ArapEnergy::spokes_and_rims)
        cell_terms.emplace_back(t.node[static_cast<std::size_t>(c)], id, w);
    }
  RowSparse cells(node_count, static_cast<Eigen::Index>(edge_ends.size()));
  cells.setFromTriplets(cell_terms.begin(), cell_terms.end());

  // b_i = Σ over the cells c holding an edge (i, k): w / (cells per edge) R_c (p_i − p_k) (eq. 12):
  // per node its terms (cell, vector), built in place rather than through a triplet list (whose
  // fresh memory, 6 triplets per cell edge, cost more than the rest of the precompute). Cells are
  // visited in order, so a node's terms come sorted by cell and a repeat is always the last term.
  const double share = 1.0 / cells_per_edge(options.energy);
  std::vector<int> slots(static_cast<std::size_t>(node_count) + 1, 0);
  for (int n = 0; n < node_count; ++n)
    for (RowSparse::InnerIterator it(cells, n); it; ++it) {
      const auto [a, b] = edge_ends[static_cast<std::size_t>(it.col())];
      ++slots[static_cast<std::size_t>(a) + 1];
      ++slots[static_cast<std::size_t>(b) + 1];
    }
  for (std::size_t n = 1; n < slots.size(); ++n) slots[n] += slots[n - 1];
  std::vector<ArapRhsTerm>& terms = data.rhs_;
  terms.resize(static_cast<std::size_t>(slots.back()));
  std::vector<int> filled(slots.begin(), slots.end() - 1);
  const auto add = [&](int node, int cell, const Eigen::Vector3d& v) {
    int& end = filled[static_cast<std::size_t>(node)];
    if (end > slots[static_cast<std::size_t>(node)] && terms[static_cast<std::size_t>(end) - 1].cell == cell)
      terms[static_cast<std::size_t>(end) - 1].vector += v;
    else
      terms[static_cast<std::size_t>(end++)] = {cell, v};
  };
  data.edges_.reserve(static_cast<std::size_t>(cells.nonZeros()));
  data.edge_begin_.assign(1, 0);
  data.rest_energy_.assign(static_cast<std::size_t>(node_count), 0.0);
  for (int n = 0; n < node_count; ++n) {
    for (RowSparse::InnerIterator it(cells, n); it; ++it) {
      const auto [a, b] = edge_ends[static_cast<std::size_t>(it.col())];
      const Eigen::Vector3d d = (data.rest_.row(a) - data.rest_.row(b)).transpose();
      data.edges_.push_back({a, b, it.value(), it.value() * d});
      data.rest_energy_[static_cast<std::size_t>(n)] += it.value() * d.squaredNorm();
      add(a, n, share * it.value() * d);
      add(b, n, -share * it.value() * d);
    }
    data.edge_begin_.push_back(static_cast<int>(data.edges_.size()));
  }
  // Compacted in place: a node's terms move down over the slots its repeats left unused.
  data.rhs_begin_.assign(1, 0);
  std::size_t kept = 0;
  for (int n = 0; n < node_count; ++n) {
    for (int i = slots[static_cast<std::size_t>(n)]; i < filled[static_cast<std::size_t>(n)]; ++i)
      terms[kept++] = terms[static_cast<std::size_t>(i)];
    data.rhs_begin_.push_back(static_cast<int>(kept));
  }
  terms.resize(kept);
  return data;
}

ArapReport arap_solve(const ArapData& data, const Eigen::MatrixXd& handle_positions, Eigen::MatrixXd& positions) {
  const Eigen::Index vertex_count = data.vertex_count(), node_count = data.node_count();
  if (handle_positions.cols() != 3)
    throw InvalidInputError("arap_solve: the handle positions have " + std::to_string(handle_positions.cols()) +
                            " columns, not 3");
  Eigen::MatrixXd handle_nodes;
  try {
    handle_nodes = constrained_node_values(data.system_, handle_positions);
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(std::string("arap_solve: ") + e.what());
  }
  if (positions.size() != 0 && (positions.rows() != vertex_count || positions.cols() != 3 || !positions.allFinite()))
    throw InvalidInputError("arap_solve: the initial guess must be empty or " + std::to_string(vertex_count) +
                            "x3 finite positions");
  const std::vector<int>& node = data.system_.node_of_vertex;
  const std::vector<int>& slot = data.system_.slot_of_node;
  Eigen::MatrixXd p = data.rest_;
  if (positions.size() != 0)
    for (Eigen::Index v = 0; v < vertex_count; ++v) p.row(node[static_cast<std::size_t>(v)]) = positions.row(v);
  std::vector<int> free_node(static_cast<std::size_t>(data.system_.free_by_constrained.rows()));
  for (int n = 0; n < static_cast<int>(node_count); ++n) {
    const int s = slot[static_cast<std::size_t>(n)];
    if (s >= 0)
      free_node[static_cast<std::size_t>(s)] = n;
    else
      p.row(n) = handle_nodes.row(-1 - s);
  }
  const Eigen::MatrixXd handle_rhs = data.system_.free_by_constrained * handle_nodes;

  std::vector<Eigen::Matrix3d> rotations(static_cast<std::size_t>(node_count));
  std::vector<double> cell_energy(static_cast<std::size_t>(node_count));
  const auto energy = [&] {
    local_step(data.edge_begin_, data.edges_, data.rest_energy_, data.options_, p, rotations, cell_energy);
    double sum = 0;
    for (const double e : cell_energy) sum += e;
    return sum;
  };
  ArapReport report;
  report.energies.push_back(energy());
  Eigen::MatrixXd b(static_cast<Eigen::Index>(free_node.size()), 3);
  while (report.iterations < data.options_.iterations && !free_node.empty()) {
    detail::parallel_for(
        b.rows(), data.options_.threads,
        [&](Eigen::Index begin, Eigen::Index end) {
          for (Eigen::Index s = begin; s < end; ++s) {
            const auto n = static_cast<std::size_t>(free_node[static_cast<std::size_t>(s)]);
            Eigen::Vector3d sum = handle_rhs.row(s).transpose();
            for (int t = data.rhs_begin_[n]; t < data.rhs_begin_[n + 1]; ++t) {
              const ArapRhsTerm& term = data.rhs_[static_cast<std::size_t>(t)];
              sum.noalias() += rotations[static_cast<std::size_t>(term.cell)] * term.vector;
            }
            b.row(s) = sum.transpose();
          }
        },
        kMinArapPart);
    // The three back-substitutions are independent: one column a part.
    Eigen::MatrixXd x(b.rows(), 3);
    detail::parallel_for(
        3, data.options_.threads,
        [&](Eigen::Index begin, Eigen::Index end) {
          for (Eigen::Index c = begin; c < end; ++c) x.col(c) = data.system_.ldlt->solve(b.col(c));
        },
        1);
    if (data.system_.ldlt->info() != Eigen::Success || !x.allFinite())
      throw SolverError("arap_solve: the solve failed (non-finite result)");
    for (std::size_t s = 0; s < free_node.size(); ++s) p.row(free_node[s]) = x.row(static_cast<Eigen::Index>(s));
    ++report.iterations;
    const double previous = report.energies.back();
    report.energies.push_back(energy());
    if (data.options_.tolerance > 0 &&
        previous - report.energies.back() <= data.options_.tolerance * std::abs(previous))
      break;
  }
  positions.resize(vertex_count, 3);
  for (Eigen::Index v = 0; v < vertex_count; ++v) positions.row(v) = p.row(node[static_cast<std::size_t>(v)]);
  return report;
}

}  // namespace cgamesh::deform
