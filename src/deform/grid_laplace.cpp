#include "grid_laplace.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cgamesh/errors.hpp"

namespace cgamesh::deform::detail {

/// The 8 corners of the cell of g holding p (clamped to the grid) and their trilinear weights.
void cell_corners(const Grid& g, const Vec3& p, std::array<Eigen::Index, 8>& node, std::array<double, 8>& weight) {
  const Vec3 t = (p - g.origin) / g.h;
  std::array<int, 3> cell{};
  Vec3 s;
  for (int a = 0; a < 3; ++a) {
    cell[static_cast<std::size_t>(a)] = std::clamp(static_cast<int>(std::floor(t[a])), 0, g.n[a] - 2);
    s[a] = std::clamp(t[a] - cell[static_cast<std::size_t>(a)], 0.0, 1.0);
  }
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
    weight[static_cast<std::size_t>(corner)] = (di ? s[0] : 1 - s[0]) * (dj ? s[1] : 1 - s[1]) * (dk ? s[2] : 1 - s[2]);
    node[static_cast<std::size_t>(corner)] = g.node(cell[0] + di, cell[1] + dj, cell[2] + dk);
  }
}

/// The trilinear interpolation at p of the grid values (unknowns x, boundary values `fixed`).
/// @throws SolverError when a cell corner has no value (p not inside the cage).
Eigen::Matrix<double, 1, kColumns> interpolate(const Grid& g, const Block& x, const Block& fixed, const Vec3& p) {
  std::array<Eigen::Index, 8> node{};
  std::array<double, 8> weight{};
  cell_corners(g, p, node, weight);
  Eigen::Matrix<double, 1, kColumns> sum = Eigen::Matrix<double, 1, kColumns>::Zero();
  for (std::size_t c = 0; c < 8; ++c) {
    if (weight[c] == 0) continue;
    const int slot = g.slot[static_cast<std::size_t>(node[c])];
    if (slot == -1) throw SolverError("cage: a point to interpolate is outside the cage's grid");
    sum += weight[c] * (slot >= 0 ? x.row(slot) : fixed.row(-2 - slot));
  }
  return sum;
}

/// Conjugate gradients on the 7-point Laplacian of the finest grid's unknowns, preconditioned by
/// the multigrid V-cycle, every column its own system in lockstep: 6 xᵤ − Σ neighbours = 0 with
/// the boundary values moved to the right-hand side.
/// @param[out] x  #unknowns × kColumns solution
/// @throws SolverError when a column does not converge.
void solve_laplace(const Multigrid& mg, const Grid& g, std::size_t level, const Block& fixed, double tolerance, Block& x) {
  const Eigen::Index n = static_cast<Eigen::Index>(g.unknown_node.size());
  using Row = Eigen::Array<double, 1, kColumns>;
  Block r(n, kColumns), z(n, kColumns), p(n, kColumns), ap(n, kColumns);
  Multigrid::Workspace work = mg.workspace();
  for (Eigen::Index u = 0; u < n; ++u) {
    Row b = Row::Zero();
    for (const int o : g.neighbor[static_cast<std::size_t>(u)])
      if (o < 0) b += fixed.row(-2 - o).array();
    r.row(u) = b.matrix();
  }
  x = Block::Zero(n, kColumns);
  // A column without boundary values on this grid has the solution 0.
  const Row bb = r.colwise().squaredNorm().array().max(1e-30);
  Row rr = r.colwise().squaredNorm().array();
  mg.apply(r, z, work);
  p = z;
  Row rz = (r.array() * z.array()).colwise().sum();
  // A V-cycle preconditioner needs tens of iterations; a generous cap that only a broken system
  // reaches.
  constexpr int kMaxIterations = 500;
  for (int it = 0; it < kMaxIterations; ++it) {
    if ((rr <= tolerance * tolerance * bb).all()) return;
    mg.laplacian(level, p, ap);
    const Row pap = (p.array() * ap.array()).colwise().sum();
    const Row alpha = (pap > 0).select(rz / pap, 0.0);
    x.array() += p.array().rowwise() * alpha;
    r.array() -= ap.array().rowwise() * alpha;
    rr = r.colwise().squaredNorm().array();
    mg.apply(r, z, work);
    const Row next = (r.array() * z.array()).colwise().sum();
    const Row beta = (rz > 0).select(next / rz, 0.0);
    rz = next;
    p.array() = z.array() + p.array().rowwise() * beta;
  }
  throw SolverError("cage: the grid Laplace solves did not converge in " + std::to_string(kMaxIterations) +
                    " iterations");
}

}  // namespace cgamesh::deform::detail
