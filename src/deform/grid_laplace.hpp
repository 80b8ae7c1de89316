#pragma once
// The Laplace equation on a regular grid, solved for cage_coordinates() (Joshi et al. 2007,
// section 3.1): the unknown nodes of the 7-point stencil with Dirichlet values at boundary nodes,
// kColumns right-hand sides at a time, by conjugate gradients preconditioned with a multigrid
// V-cycle over the grids of halving resolutions; trilinear interpolation of the solution.

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace cgamesh::deform::detail {

using Vec3 = Eigen::Vector3d;

/// Right-hand sides (cage vertices) solved together: one cache line of doubles per grid node.
constexpr int kColumns = 8;
using Block = Eigen::Matrix<double, Eigen::Dynamic, kColumns, Eigen::RowMajor>;

/// Resolution of the coarsest multigrid level, solved exactly (≤ 13³ nodes).
constexpr int kCoarsestResolution = 8;

/// A boundary node's value: the barycentric coordinates of its closest boundary point on one
/// face of the boundary surface.
struct BoundaryValue {
  int face = 0;
  Vec3 barycentric = Vec3::Zero();
};

/// The grid of one resolution over the cage's box.
struct Grid {
  Vec3 origin = Vec3::Zero();
  double h = 1;
  std::array<int, 3> n{};  ///< nodes per axis
  /// Per node: ≥ 0 its unknown index; −2 − b its boundary value b; −1 unused (outside).
  std::vector<int> slot;
  std::vector<BoundaryValue> boundary;
  std::vector<int> unknown_node;  ///< node of each unknown
  /// Per unknown, its 6 neighbours: ≥ 0 an unknown, else −2 − b a boundary value.
  std::vector<std::array<int, 6>> neighbor;

  [[nodiscard]] Eigen::Index node(int i, int j, int k) const {
    return i + static_cast<Eigen::Index>(n[0]) * (j + static_cast<Eigen::Index>(n[1]) * k);
  }
  [[nodiscard]] Vec3 position(Eigen::Index node) const {
    const Eigen::Index i = node % n[0], j = (node / n[0]) % n[1], k = node / (static_cast<Eigen::Index>(n[0]) * n[1]);
    return origin + h * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
  }
};

/// The 8 corners of the cell of g holding p (clamped to the grid) and their trilinear weights.
void cell_corners(const Grid& g, const Vec3& p, std::array<Eigen::Index, 8>& node, std::array<double, 8>& weight);

/// The trilinear interpolation at p of the grid values (unknowns x, boundary values `fixed`).
/// @throws SolverError when a cell corner has no value (p not inside the cage).
[[nodiscard]] Eigen::Matrix<double, 1, kColumns> interpolate(const Grid& g, const Block& x, const Block& fixed, const Vec3& p);

/// A multigrid V-cycle over the grids of halving resolutions (coarsest first) as the
/// preconditioner of conjugate gradients: Richardson smoothing (the stencil's diagonal is the
/// constant 6, so Jacobi is a polynomial in the Laplacian), trilinear prolongation P, restriction
/// its transpose, the coarsest grid solved exactly. Same smoothing before and after and R ∝ Pᵀ
/// keep the preconditioner symmetric, as CG needs.
class Multigrid {
 public:
  explicit Multigrid(const std::vector<Grid>& grids) : grids_(grids), prolongation_(grids.size()) {
    for (std::size_t level = 1; level < grids.size(); ++level) {
      const Grid &coarse = grids[level - 1], &fine = grids[level];
      Prolongation& p = prolongation_[level];
      p.offset.push_back(0);
      std::array<Eigen::Index, 8> node{};
      std::array<double, 8> weight{};
      for (const int u : fine.unknown_node) {
        cell_corners(coarse, fine.position(u), node, weight);
        for (std::size_t c = 0; c < 8; ++c) {
          const int slot = coarse.slot[static_cast<std::size_t>(node[c])];
          // The correction is 0 on the boundary: only coarse unknowns contribute.
          if (weight[c] > 0 && slot >= 0) {
            p.index.push_back(slot);
            p.weight.push_back(weight[c]);
          }
        }
        p.offset.push_back(static_cast<int>(p.index.size()));
      }
      p.scale = std::pow(coarse.h / fine.h, 2) / 8;
    }
    const Grid& g = grids.front();
    const Eigen::Index n = static_cast<Eigen::Index>(g.unknown_node.size());
    Eigen::MatrixXd a = 6 * Eigen::MatrixXd::Identity(n, n);
    for (Eigen::Index u = 0; u < n; ++u)
      for (const int o : g.neighbor[static_cast<std::size_t>(u)])
        if (o >= 0) a(u, o) = -1;
    coarsest_.compute(a);
  }

  /// Per level, the buffers of one thread's cycles (allocated once: in a cycle, fresh pages would
  /// cost more than the arithmetic).
  struct Workspace {
    std::vector<Block> r, e, ae;
  };
  [[nodiscard]] Workspace workspace() const {
    Workspace w;
    for (const Grid& g : grids_) {
      const Eigen::Index n = static_cast<Eigen::Index>(g.unknown_node.size());
      w.r.emplace_back(n, kColumns);
      w.e.emplace_back(n, kColumns);
      w.ae.emplace_back(n, kColumns);
    }
    return w;
  }

  /// z = M r on the finest grid.
  void apply(const Block& r, Block& z, Workspace& w) const { cycle(grids_.size() - 1, r, z, w); }

  /// out = A v on the unknowns of `level` (boundary values 0); out is sized.
  void laplacian(std::size_t level, const Block& v, Block& out) const {
    const Grid& g = grids_[level];
    for (Eigen::Index u = 0; u < v.rows(); ++u) {
      Eigen::Array<double, 1, kColumns> a = 6 * v.row(u).array();
      for (const int o : g.neighbor[static_cast<std::size_t>(u)])
        if (o >= 0) a -= v.row(o).array();
      out.row(u) = a.matrix();
    }
  }

 private:
  struct Prolongation {
    std::vector<int> offset, index;  ///< per fine unknown, its coarse unknowns [offset[u], offset[u + 1])
    std::vector<double> weight;
    double scale = 0;  ///< restriction = scale Pᵀ: the average, times (H / h)² for the coarse stencil
  };

  /// e ≈ A⁻¹ r on `level`.
  void cycle(std::size_t level, const Block& r, Block& e, Workspace& w) const {
    if (level == 0) {
      e = coarsest_.solve(r);
      return;
    }
    // ω = 6/7: the Richardson weight that damps the high frequencies of the 7-point stencil best.
    constexpr double kStep = 1.0 / 7;
    Block& ae = w.ae[level];
    e = kStep * r;
    laplacian(level, e, ae);
    ae = r - ae;  // the residual
    const Prolongation& p = prolongation_[level];
    Block &coarse_r = w.r[level - 1], &coarse_e = w.e[level - 1];
    coarse_r.setZero();
    for (Eigen::Index u = 0; u < r.rows(); ++u)
      for (int k = p.offset[static_cast<std::size_t>(u)]; k < p.offset[static_cast<std::size_t>(u) + 1]; ++k)
        coarse_r.row(p.index[static_cast<std::size_t>(k)]) +=
            (p.scale * p.weight[static_cast<std::size_t>(k)]) * ae.row(u);
    cycle(level - 1, coarse_r, coarse_e, w);
    for (Eigen::Index u = 0; u < r.rows(); ++u)
      for (int k = p.offset[static_cast<std::size_t>(u)]; k < p.offset[static_cast<std::size_t>(u) + 1]; ++k)
        e.row(u) += p.weight[static_cast<std::size_t>(k)] * coarse_e.row(p.index[static_cast<std::size_t>(k)]);
    laplacian(level, e, ae);
    e += kStep * (r - ae);
  }

  const std::vector<Grid>& grids_;
  std::vector<Prolongation> prolongation_;
  Eigen::LLT<Eigen::MatrixXd> coarsest_;
};

/// Conjugate gradients on the 7-point Laplacian of the finest grid's unknowns, preconditioned by
/// the multigrid V-cycle, every column its own system in lockstep: 6 xᵤ − Σ neighbours = 0 with
/// the boundary values moved to the right-hand side.
/// @param[out] x  #unknowns × kColumns solution
/// @throws SolverError when a column does not converge.
void solve_laplace(const Multigrid& mg, const Grid& g, std::size_t level, const Block& fixed, double tolerance, Block& x);

}  // namespace cgamesh::deform::detail
