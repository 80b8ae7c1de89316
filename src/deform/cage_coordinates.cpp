#include "cgamesh/deform/cage_coordinates.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "cgamesh/cga/exp_log.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"

#include "../parallel_for.hpp"
#include "generator_table.hpp"

namespace cgamesh::deform {
namespace {

using Vec3 = Eigen::Vector3d;

/// Cage vertices solved together: one cache line of doubles per grid node.
constexpr int kColumns = 8;
using Block = Eigen::Matrix<double, Eigen::Dynamic, kColumns, Eigen::RowMajor>;

/// Resolution of the coarsest multigrid level, solved exactly (≤ 13³ nodes).
constexpr int kCoarsestResolution = 8;

/// Boundary nodes lie within √3 cells of the cage (a cell corner of an inside point), with room
/// for rounding.
constexpr double kBandCells = 1.75;

Vec3 cage_vertex(const Cage& cage, int j) { return cage.vertices.row(j).transpose(); }

/// The solid angle of triangle abc seen from the origin (Van Oosterom & Strackee 1983), signed
/// by the orientation: the generalised winding number is Σ Ω / 4π.
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double det = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2 * std::atan2(det, denominator);
}

/// |winding number| of the cage around p: 1 inside a closed oriented cage, 0 outside, either
/// orientation; ≈ ½ on the surface.
double winding(const Cage& cage, const Vec3& p) {
  double sum = 0;
  for (Eigen::Index f = 0; f < cage.faces.rows(); ++f)
    sum += solid_angle(cage_vertex(cage, cage.faces(f, 0)) - p, cage_vertex(cage, cage.faces(f, 1)) - p,
                       cage_vertex(cage, cage.faces(f, 2)) - p);
  return std::abs(sum) / (4 * std::numbers::pi);
}

/// The point of triangle abc closest to p as barycentric coordinates (Ericson, Real-Time
/// Collision Detection, 5.1.5).
Vec3 closest_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denominator = 1 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return {1 - v - w, v, w};
}

/// A boundary node's value: the barycentric coordinates of its closest cage point on one face.
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

Grid make_grid(const Cage& cage, int resolution, int threads) {
  const Vec3 lo = cage.vertices.colwise().minCoeff().transpose();
  const Vec3 hi = cage.vertices.colwise().maxCoeff().transpose();
  Grid g;
  g.h = (hi - lo).maxCoeff() / resolution;
  constexpr int kPad = 2;  // ≥ kBandCells: the boundary nodes outside the box are on the grid
  g.origin = lo - Vec3::Constant(kPad * g.h);
  for (int a = 0; a < 3; ++a) g.n[a] = static_cast<int>(std::ceil((hi[a] - lo[a]) / g.h - 1e-9)) + 1 + 2 * kPad;
  const Eigen::Index count = static_cast<Eigen::Index>(g.n[0]) * g.n[1] * g.n[2];
  // Per node: 1 inside, else the boundary value's face + 2 (≥ 2), or 0.
  std::vector<int> kind(static_cast<std::size_t>(count), 0);
  std::vector<Vec3> barycentric(static_cast<std::size_t>(count));
  const double band = kBandCells * g.h;
  detail::parallel_for(count, threads, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index v = begin; v < end; ++v) {
      const Vec3 p = g.position(v);
      if (winding(cage, p) >= 0.5) {
        kind[static_cast<std::size_t>(v)] = 1;
        continue;
      }
      if ((lo - p).maxCoeff() > band || (p - hi).maxCoeff() > band) continue;
      double best = band * band;
      for (Eigen::Index f = 0; f < cage.faces.rows(); ++f) {
        const Vec3 a = cage_vertex(cage, cage.faces(f, 0)), b = cage_vertex(cage, cage.faces(f, 1)),
                   c = cage_vertex(cage, cage.faces(f, 2));
        const Vec3 w = closest_barycentric(p, a, b, c);
        const double d = (w[0] * a + w[1] * b + w[2] * c - p).squaredNorm();
        if (d <= best) {
          best = d;
          kind[static_cast<std::size_t>(v)] = static_cast<int>(f) + 2;
          barycentric[static_cast<std::size_t>(v)] = w;
        }
      }
    }
  });
  g.slot.assign(static_cast<std::size_t>(count), -1);
  for (Eigen::Index v = 0; v < count; ++v) {
    const int k = kind[static_cast<std::size_t>(v)];
    if (k == 1) {
      g.slot[static_cast<std::size_t>(v)] = static_cast<int>(g.unknown_node.size());
      g.unknown_node.push_back(static_cast<int>(v));
    } else if (k >= 2) {
      g.slot[static_cast<std::size_t>(v)] = -2 - static_cast<int>(g.boundary.size());
      g.boundary.push_back({k - 2, barycentric[static_cast<std::size_t>(v)]});
    }
  }
  const std::array<Eigen::Index, 3> stride = {1, g.n[0], static_cast<Eigen::Index>(g.n[0]) * g.n[1]};
  g.neighbor.resize(g.unknown_node.size());
  for (std::size_t u = 0; u < g.unknown_node.size(); ++u)
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s) {
        const int other = g.slot[static_cast<std::size_t>(g.unknown_node[u] + (s ? 1 : -1) * stride[a])];
        // An inside node's neighbour is inside or within a cell of the cage (so a boundary node):
        // only a winding number misjudged by rounding on the surface could break this.
        if (other == -1) throw SolverError("cage: grid node next to the cage has no boundary value");
        g.neighbor[u][static_cast<std::size_t>(2 * a + s)] = other;
      }
  return g;
}

/// The boundary values of `columns` (cage vertices, −1 for unused lanes): #boundary × kColumns.
Block boundary_values(const Grid& g, const Cage& cage, const std::array<int, kColumns>& columns) {
  Block out = Block::Zero(static_cast<Eigen::Index>(g.boundary.size()), kColumns);
  for (std::size_t b = 0; b < g.boundary.size(); ++b)
    for (int corner = 0; corner < 3; ++corner)
      for (int c = 0; c < kColumns; ++c)
        if (cage.faces(g.boundary[b].face, corner) == columns[static_cast<std::size_t>(c)])
          out(static_cast<Eigen::Index>(b), c) += g.boundary[b].barycentric[corner];
  return out;
}

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
void solve(const Multigrid& mg, const Grid& g, std::size_t level, const Block& fixed, double tolerance, Block& x) {
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

Cage to_cage(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& faces) {
  Cage cage;
  cage.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t v = 0; v < vertices.size(); ++v) cage.vertices.row(static_cast<Eigen::Index>(v)) = vertices[v];
  cage.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    cage.faces.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  return cage;
}

}  // namespace

Cage read_cage_obj(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw FileError("cannot read the cage " + path.string() + ": is a directory");
  std::ifstream in(path);
  if (!in) throw FileError("cannot read the cage " + path.string());
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> faces;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    const auto bad = [&](const std::string& what) {
      throw FileError("cage " + path.string() + ":" + std::to_string(number) + ": " + what);
    };
    if (tag == "v") {
      Vec3 v;
      if (!(words >> v[0] >> v[1] >> v[2]) || !v.allFinite()) bad("expected v x y z (finite numbers)");
      vertices.push_back(v);
    } else if (tag == "f") {
      std::vector<int> corners;
      for (std::string word; words >> word;) {
        long long index = 0;
        try {
          std::size_t used = 0;
          index = std::stoll(word, &used);
          if (used < word.size() && word[used] != '/') throw std::invalid_argument(word);
        } catch (const std::exception&) {
          bad("expected f with vertex indices, got '" + word + "'");
        }
        // OBJ indices start at 1; negative ones count back from the last vertex so far.
        const long long resolved = index > 0 ? index - 1 : static_cast<long long>(vertices.size()) + index;
        if (index == 0 || resolved < 0 || resolved >= static_cast<long long>(vertices.size()))
          bad("vertex index " + word + " out of range (" + std::to_string(vertices.size()) + " vertices so far)");
        corners.push_back(static_cast<int>(resolved));
      }
      if (corners.size() < 3) bad("a face needs 3 vertices or more");
      for (std::size_t c = 1; c + 1 < corners.size(); ++c) faces.push_back({corners[0], corners[c], corners[c + 1]});
    }
  }
  return to_cage(vertices, faces);
}

Cage box_cage(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const std::array<int, 3>& cuts) {
  if (!lo.allFinite() || !hi.allFinite() || !(hi.array() > lo.array()).all())
    throw InvalidInputError("box cage: expected finite corners with lo < hi on every axis");
  if (std::any_of(cuts.begin(), cuts.end(), [](int c) { return c < 1; }))
    throw InvalidInputError("box cage: expected at least 1 segment per axis");
  std::map<std::array<int, 3>, int> index;  // lattice point on the surface → vertex
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> faces;
  const auto vertex = [&](const std::array<int, 3>& q) {
    const auto [it, added] = index.emplace(q, static_cast<int>(vertices.size()));
    if (added)
      vertices.push_back(lo +
                         (hi - lo).cwiseProduct(Vec3(q[0], q[1], q[2]).cwiseQuotient(Vec3(cuts[0], cuts[1], cuts[2]))));
    return it->second;
  };
  for (std::size_t a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const std::size_t b = (a + 1) % 3, c = (a + 2) % 3;
      for (int i = 0; i < cuts[b]; ++i)
        for (int j = 0; j < cuts[c]; ++j) {
          std::array<int, 4> v{};
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> q{};
            q[a] = side * cuts[a];
            q[b] = i + (k == 1 || k == 2);
            q[c] = j + (k >= 2);
            v[static_cast<std::size_t>(k)] = vertex(q);
          }
          // (b, c) turns counter-clockwise about +a: outward on the + side.
          if (side == 0) std::swap(v[1], v[3]);
          faces.push_back({v[0], v[1], v[2]});
          faces.push_back({v[0], v[2], v[3]});
        }
    }
  return to_cage(vertices, faces);
}

void check_cage(const Cage& cage) {
  const Eigen::Index nv = cage.vertices.rows(), nf = cage.faces.rows();
  if (nv < 4 || nf < 4)
    throw InvalidInputError("cage: " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                            " faces; a closed cage needs at least 4 of each");
  if (!cage.vertices.allFinite()) throw InvalidInputError("cage: a vertex is not finite");
  if ((cage.faces.array() < 0).any() || (cage.faces.array() >= static_cast<int>(nv)).any())
    throw InvalidInputError("cage: a face index is outside [0, " + std::to_string(nv) + ")");
  std::map<std::pair<int, int>, int> directed;  // directed edge → faces using it
  std::map<std::pair<int, int>, int> undirected;
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const int a = cage.faces(f, 0), b = cage.faces(f, 1), c = cage.faces(f, 2);
    if (a == b || b == c || c == a)
      throw TopologyError("cage: face " + std::to_string(f) + " repeats a vertex (degenerate)");
    for (int k = 0; k < 3; ++k) {
      const int from = cage.faces(f, k), to = cage.faces(f, (k + 1) % 3);
      used[static_cast<std::size_t>(from)] = 1;
      ++directed[{from, to}];
      ++undirected[{std::min(from, to), std::max(from, to)}];
    }
  }
  for (const auto& [edge, count] : undirected) {
    const std::string name = "cage: edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second);
    if (count == 1) throw TopologyError(name + " has one face: the cage is not closed");
    if (count > 2) throw TopologyError(name + " has " + std::to_string(count) + " faces: the cage is not manifold");
    if (directed[edge] != 1)
      throw TopologyError(name + " runs the same way in both its faces: the cage is not consistently oriented");
  }
  for (Eigen::Index v = 0; v < nv; ++v)
    if (!used[static_cast<std::size_t>(v)]) throw TopologyError("cage: vertex " + std::to_string(v) + " is on no face");
}

Eigen::MatrixXd cage_coordinates(const mesh::RowMatrixXf<3>& rest, const Cage& cage, const CageOptions& options) {
  check_cage(cage);
  if (options.resolution < kMinCageResolution || options.resolution > kMaxCageResolution)
    throw InvalidInputError("cage: the resolution must be in [" + std::to_string(kMinCageResolution) + ", " +
                            std::to_string(kMaxCageResolution) + "]");
  if (!(options.tolerance > 0 && options.tolerance < 1))
    throw InvalidInputError("cage: the tolerance must be in (0, 1)");
  const Eigen::Index nv = rest.rows();
  std::vector<double> inside(static_cast<std::size_t>(nv));
  detail::parallel_for(nv, options.threads, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i)
      inside[static_cast<std::size_t>(i)] = winding(cage, rest.row(i).transpose().cast<double>());
  });
  for (Eigen::Index i = 0; i < nv; ++i)
    if (!(inside[static_cast<std::size_t>(i)] >= 0.5)) {
      std::ostringstream where;
      where << rest.row(i);
      const bool labelled = options.vertex_labels.size() == static_cast<std::size_t>(nv) &&
                            options.vertex_labels[static_cast<std::size_t>(i)] >= 0;
      throw InvalidInputError("cage: vertex " +
                              std::to_string(labelled ? options.vertex_labels[static_cast<std::size_t>(i)] : i) +
                              " at (" + where.str() + ") is outside the cage (winding number " +
                              std::to_string(inside[static_cast<std::size_t>(i)]) + ")");
    }

  // The multigrid hierarchy: grids of halving resolution down to kCoarsestResolution.
  std::vector<int> resolutions = {options.resolution};
  while (resolutions.back() / 2 >= kCoarsestResolution) resolutions.push_back(resolutions.back() / 2);
  std::reverse(resolutions.begin(), resolutions.end());
  std::vector<Grid> grids;
  for (const int r : resolutions) grids.push_back(make_grid(cage, r, options.threads));
  const Multigrid multigrid(grids);

  const Eigen::Index nc = cage.vertices.rows();
  const int blocks = static_cast<int>((nc + kColumns - 1) / kColumns);
  Eigen::MatrixXd out(nv, nc);
  // Blocks of cage vertices go to the threads: each block's solves are independent.
  std::atomic<int> next{0};
  std::vector<std::exception_ptr> errors;
  auto worker = [&](std::exception_ptr& error) {
    try {
      for (int block; (block = next++) < blocks;) {
        std::array<int, kColumns> columns{};
        for (int c = 0; c < kColumns; ++c) {
          const Eigen::Index column = static_cast<Eigen::Index>(block) * kColumns + c;
          columns[static_cast<std::size_t>(c)] = column < nc ? static_cast<int>(column) : -1;
        }
        const Block fixed = boundary_values(grids.back(), cage, columns);
        Block x;
        solve(multigrid, grids.back(), grids.size() - 1, fixed, options.tolerance, x);
        for (Eigen::Index i = 0; i < nv; ++i) {
          const auto values = interpolate(grids.back(), x, fixed, rest.row(i).transpose().cast<double>());
          for (int c = 0; c < kColumns; ++c)
            if (columns[static_cast<std::size_t>(c)] >= 0) out(i, columns[static_cast<std::size_t>(c)]) = values[c];
        }
      }
    } catch (...) {
      error = std::current_exception();
    }
  };
  const int threads = std::min(options.threads > 0 ? options.threads : detail::hardware_threads(), blocks);
  errors.resize(static_cast<std::size_t>(threads));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, std::ref(errors[static_cast<std::size_t>(t)]));
  worker(errors[0]);
  for (auto& t : pool) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
  // Harmonic functions with boundary values ≥ 0 summing to 1 do the same; the solver's and the
  // rounding's residue is removed so that the rows are coordinates exactly.
  out = out.cwiseMax(0.0);
  for (Eigen::Index i = 0; i < nv; ++i) out.row(i) /= out.row(i).sum();
  return out;
}

namespace {

constexpr char kNpyMagic[] = "\x93NUMPY";

}  // namespace

void save_cage_coordinates(const std::filesystem::path& path, const Eigen::MatrixXd& coordinates) {
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(coordinates.rows()) +
                       ", " + std::to_string(coordinates.cols()) + "), }";
  // Format 1.0: magic, version, a 2-byte length, the header padded with spaces and a newline so
  // that the data starts at a multiple of 64 bytes.
  const std::size_t unpadded = 6 + 2 + 2 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  std::string bytes(kNpyMagic, 6);
  bytes += '\x01';
  bytes += '\x00';
  bytes += static_cast<char>(header.size() & 0xff);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = coordinates;
  static_assert(std::endian::native == std::endian::little, "the .npy writer assumes a little-endian machine");
  bytes.append(reinterpret_cast<const char*>(rows.data()), static_cast<std::size_t>(rows.size()) * sizeof(double));
  io::write_file_atomically(path, bytes);
}

Eigen::MatrixXd load_cage_coordinates(const std::filesystem::path& path, Eigen::Index vertices, Eigen::Index cage) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) throw FileError("cannot read the coordinates " + path.string());
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto bad = [&](const std::string& what) -> FileError {
    return FileError("coordinates " + path.string() + ": " + what);
  };
  if (bytes.size() < 10 || bytes.compare(0, 6, kNpyMagic, 6) != 0) throw bad("not a .npy file");
  const auto major = static_cast<unsigned char>(bytes[6]);
  std::size_t length = 0, start = 0;
  if (major == 1) {
    length = static_cast<unsigned char>(bytes[8]) | static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8;
    start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw bad("truncated header");
    for (int b = 0; b < 4; ++b) length |= static_cast<std::size_t>(static_cast<unsigned char>(bytes[8 + b])) << (8 * b);
    start = 12;
  } else {
    throw bad("unknown .npy version " + std::to_string(major));
  }
  if (bytes.size() < start + length) throw bad("truncated header");
  std::string header = bytes.substr(start, length);
  header.erase(std::remove(header.begin(), header.end(), ' '), header.end());
  if (header.find("'descr':'<f8'") == std::string::npos) throw bad("expected float64 ('<f8') values");
  if (header.find("'fortran_order':False") == std::string::npos) throw bad("expected C order (fortran_order False)");
  const std::size_t shape = header.find("'shape':(");
  long long rows = -1, cols = -1;
  if (shape == std::string::npos || std::sscanf(header.c_str() + shape + 9, "%lld,%lld)", &rows, &cols) != 2 ||
      rows < 0 || cols < 0)
    throw bad("expected a 2-D shape");
  if (rows != vertices || cols != cage)
    throw bad("holds " + std::to_string(rows) + "x" + std::to_string(cols) + " coordinates; the mesh and cage need " +
              std::to_string(vertices) + "x" + std::to_string(cage));
  const std::size_t data = start + length;
  if (bytes.size() != data + static_cast<std::size_t>(rows * cols) * sizeof(double))
    throw bad("the data is not " + std::to_string(rows) + "x" + std::to_string(cols) + " float64 values (truncated?)");
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> values(rows, cols);
  std::memcpy(values.data(), bytes.data() + data, static_cast<std::size_t>(rows * cols) * sizeof(double));
  for (Eigen::Index i = 0; i < values.rows(); ++i)
    if (!values.row(i).allFinite() || (values.row(i).array() < -1e-9).any() || std::abs(values.row(i).sum() - 1) > 1e-6)
      throw bad("row " + std::to_string(i) + " is not coordinates (finite, >= 0, summing to 1)");
  return values;
}

CageDeformation::CageDeformation(const mesh::RowMatrixXf<3>& rest, const Cage& cage, const Eigen::MatrixXd& coordinates,
                                 const CageSparsity& sparsity, int threads)
    : rest_(rest), cage_(cage.vertices), threads_(threads) {
  if (coordinates.rows() != rest.rows() || coordinates.cols() != cage.vertices.rows())
    throw InvalidInputError("cage: " + std::to_string(coordinates.rows()) + "x" + std::to_string(coordinates.cols()) +
                            " coordinates for " + std::to_string(rest.rows()) + " vertices and " +
                            std::to_string(cage.vertices.rows()) + " cage vertices");
  if (!coordinates.allFinite()) throw InvalidInputError("cage: a coordinate is not finite");
  if (sparsity.max_weights < 1) throw InvalidInputError("cage: max_weights must be >= 1");
  if (!(sparsity.min_weight >= 0 && sparsity.min_weight < 1))
    throw InvalidInputError("cage: min_weight must be in [0, 1)");
  offset_.push_back(0);
  std::vector<std::pair<double, int>> order;
  for (Eigen::Index i = 0; i < coordinates.rows(); ++i) {
    order.clear();
    for (Eigen::Index j = 0; j < coordinates.cols(); ++j) order.emplace_back(coordinates(i, j), static_cast<int>(j));
    const auto keep = std::min<std::size_t>(order.size(), static_cast<std::size_t>(sparsity.max_weights));
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(keep), order.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
    double sum = 0;
    std::size_t kept = 0;
    // The largest is always kept, so that every vertex has a coordinate to renormalise.
    for (; kept < keep && (kept == 0 || order[kept].first >= sparsity.min_weight); ++kept) sum += order[kept].first;
    for (std::size_t k = 0; k < kept; ++k) {
      index_.push_back(order[k].second);
      weight_.push_back(static_cast<float>(order[k].first / sum));
    }
    offset_.push_back(static_cast<int>(index_.size()));
  }
}

std::vector<std::pair<int, double>> CageDeformation::weights(Eigen::Index i) const {
  std::vector<std::pair<int, double>> out;
  for (int k = offset_[static_cast<std::size_t>(i)]; k < offset_[static_cast<std::size_t>(i) + 1]; ++k)
    out.emplace_back(index_[static_cast<std::size_t>(k)], weight_[static_cast<std::size_t>(k)]);
  return out;
}

double CageDeformation::mean_weights() const noexcept {
  return rest_.rows() == 0 ? 0.0 : static_cast<double>(index_.size()) / static_cast<double>(rest_.rows());
}

template <int N>
Eigen::Matrix<float, N, 1> CageDeformation::contract(
    Eigen::Index i, const Eigen::Matrix<float, N, Eigen::Dynamic>& table) const noexcept {
  Eigen::Matrix<float, N, 1> sum = Eigen::Matrix<float, N, 1>::Zero();
  for (int k = offset_[static_cast<std::size_t>(i)]; k < offset_[static_cast<std::size_t>(i) + 1]; ++k)
    sum += weight_[static_cast<std::size_t>(k)] * table.col(index_[static_cast<std::size_t>(k)]);
  return sum;
}

template <class Job>
void CageDeformation::frame(std::size_t count, const char* what, mesh::RowMatrixXf<3>& out, Job&& job) const {
  if (static_cast<Eigen::Index>(count) != cage_.rows())
    throw InvalidInputError("cage: " + std::to_string(count) + " " + what + " given for a cage of " +
                            std::to_string(cage_.rows()) + " vertices");
  out.resize(rest_.rows(), 3);
  detail::parallel_for(rest_.rows(), threads_, job);
}

void CageDeformation::deform_points(std::span<const Eigen::Vector3d> points, mesh::RowMatrixXf<3>& out) const {
  Eigen::Matrix<float, 3, Eigen::Dynamic> displacement(3, cage_.rows());
  for (Eigen::Index c = 0; c < cage_.rows() && c < static_cast<Eigen::Index>(points.size()); ++c)
    displacement.col(c) = (points[static_cast<std::size_t>(c)] - cage_.row(c).transpose()).cast<float>();
  frame(points.size(), "cage vertices", out, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i) out.row(i) = rest_.row(i) + contract(i, displacement).transpose();
  });
}

void CageDeformation::deform_motors(std::span<const cga::Versor<double>> motors, mesh::RowMatrixXf<3>& out) const {
  Eigen::Matrix<float, detail::kGeneratorSize, Eigen::Dynamic> logs;
  if (static_cast<Eigen::Index>(motors.size()) == cage_.rows()) detail::fill_log_table(motors, logs);
  frame(motors.size(), "cage vertex motors", out, [&](Eigen::Index begin, Eigen::Index end) {
    detail::exp_apply_range(rest_, begin, end, out, [&](Eigen::Index i) { return contract(i, logs); });
  });
}

}  // namespace cgamesh::deform
