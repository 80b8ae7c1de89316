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
#include "cgamesh/io/npy.hpp"
#include "cgamesh/io/obj_reader.hpp"

#include "../parallel_for.hpp"
#include "generator_table.hpp"
#include "grid_laplace.hpp"

namespace cgamesh::deform {
namespace {

using detail::Block;
using detail::Grid;
using detail::kColumns;
using detail::Vec3;

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
  cgamesh::detail::parallel_for(count, threads, [&](Eigen::Index begin, Eigen::Index end) {
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






}  // namespace

Cage read_cage_obj(const std::filesystem::path& path) {
  io::ObjPolygons obj = io::read_obj(path, {.strict = true, .what = "cage"});
  return {std::move(obj.vertices), std::move(obj.faces)};
}

namespace {

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
  cgamesh::detail::parallel_for(nv, options.threads, [&](Eigen::Index begin, Eigen::Index end) {
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

  // The multigrid hierarchy: grids of halving resolution down to detail::kCoarsestResolution.
  std::vector<int> resolutions = {options.resolution};
  while (resolutions.back() / 2 >= detail::kCoarsestResolution) resolutions.push_back(resolutions.back() / 2);
  std::reverse(resolutions.begin(), resolutions.end());
  std::vector<Grid> grids;
  for (const int r : resolutions) grids.push_back(make_grid(cage, r, options.threads));
  const detail::Multigrid multigrid(grids);

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
        detail::solve_laplace(multigrid, grids.back(), grids.size() - 1, fixed, options.tolerance, x);
        for (Eigen::Index i = 0; i < nv; ++i) {
          const auto values = detail::interpolate(grids.back(), x, fixed, rest.row(i).transpose().cast<double>());
          for (int c = 0; c < kColumns; ++c)
            if (columns[static_cast<std::size_t>(c)] >= 0) out(i, columns[static_cast<std::size_t>(c)]) = values[c];
        }
      }
    } catch (...) {
      error = std::current_exception();
    }
  };
  const int threads = std::min(options.threads > 0 ? options.threads : cgamesh::detail::hardware_threads(), blocks);
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

void save_cage_coordinates(const std::filesystem::path& path, const Eigen::MatrixXd& coordinates) {
  io::write_npy(path, coordinates);
}

Eigen::MatrixXd load_cage_coordinates(const std::filesystem::path& path, Eigen::Index vertices, Eigen::Index cage) {
  const Eigen::MatrixXd values = io::read_npy(path, "coordinates");
  const auto bad = [&](const std::string& what) {
    throw FileError("coordinates " + path.string() + ": " + what);
  };
  if (values.rows() != vertices || values.cols() != cage)
    bad("holds " + std::to_string(values.rows()) + "x" + std::to_string(values.cols()) +
        " coordinates; the mesh and cage need " + std::to_string(vertices) + "x" + std::to_string(cage));
  for (Eigen::Index i = 0; i < values.rows(); ++i)
    if (!values.row(i).allFinite() || (values.row(i).array() < -1e-9).any() || std::abs(values.row(i).sum() - 1) > 1e-6)
      bad("row " + std::to_string(i) + " is not coordinates (finite, >= 0, summing to 1)");
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
  cgamesh::detail::parallel_for(rest_.rows(), threads_, job);
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
  Eigen::Matrix<float, cgamesh::detail::kGeneratorSize, Eigen::Dynamic> logs;
  if (static_cast<Eigen::Index>(motors.size()) == cage_.rows()) cgamesh::detail::fill_log_table(motors, logs);
  frame(motors.size(), "cage vertex motors", out, [&](Eigen::Index begin, Eigen::Index end) {
    cgamesh::detail::exp_apply_range(rest_, begin, end, out, [&](Eigen::Index i) { return contract(i, logs); });
  });
}

}  // namespace cgamesh::deform
