#include "cgamesh/deform/ffd.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/LU>

#include "cgamesh/cga/exp_log.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/errors.hpp"

#include "../parallel_for.hpp"
#include "generator_table.hpp"

namespace cgamesh::deform {
namespace {

/// Lattice coordinates this far outside [0, 1] still count as inside (rounding of the box).
constexpr double kInsideTolerance = 1e-9;

/// The l basis values of one axis at t ∈ [0, 1] into `out` (size l).
void axis_basis(const Lattice& lattice, int l, double t, std::vector<double>& out) {
  std::fill(out.begin(), out.end(), 0.0);
  if (lattice.basis == LatticeBasis::bernstein) {
    // B_u(t) = C(l−1, u) tᵘ (1 − t)^(l−1−u) (eq. 6).
    double binomial = 1;
    for (int u = 0; u < l; ++u) {
      out[static_cast<std::size_t>(u)] = binomial * std::pow(t, u) * std::pow(1 - t, l - 1 - u);
      binomial = binomial * (l - 1 - u) / (u + 1);
    }
    return;
  }
  // Uniform cubic B-spline with knots at the control points: points ui − 1 … ui + 2 act on span ui.
  const double x = t * (l - 1);
  const int span = std::clamp(static_cast<int>(std::floor(x)), 0, l - 2);
  const double s = x - span, s2 = s * s, s3 = s2 * s;
  const double b[4] = {(1 - s) * (1 - s) * (1 - s) / 6, (3 * s3 - 6 * s2 + 4) / 6, (-3 * s3 + 3 * s2 + 3 * s + 1) / 6,
                       s3 / 6};
  for (int j = 0; j < 4; ++j) {
    const int p = span - 1 + j;
    // A missing end neighbour: repeated (Blender) or continued linearly, P₋₁ = 2P₀ − P₁.
    const int end = p < 0 ? 0 : l - 1, next = p < 0 ? 1 : l - 2;
    if (p >= 0 && p < l) {
      out[static_cast<std::size_t>(p)] += b[j];
    } else if (lattice.ends == BsplineEnds::repeat) {
      out[static_cast<std::size_t>(end)] += b[j];
    } else {
      out[static_cast<std::size_t>(end)] += 2 * b[j];
      out[static_cast<std::size_t>(next)] -= b[j];
    }
  }
}

void check_lattice(const Lattice& lattice) {
  for (int a = 0; a < 3; ++a)
    if (lattice.resolution[static_cast<std::size_t>(a)] < 2 ||
        lattice.resolution[static_cast<std::size_t>(a)] > kMaxLatticeResolution)
      throw InvalidInputError("lattice: the resolution must be in [2, " + std::to_string(kMaxLatticeResolution) +
                              "] on every axis");
  const LatticeBox& box = lattice.box;
  if (!box.origin.allFinite()) throw InvalidInputError("lattice: the box origin is not finite");
  if (!box.size.allFinite() || !(box.size.array() > 0).all())
    throw InvalidInputError("lattice: the box size must be finite and > 0 on every axis");
  if (!box.rotation.allFinite() || !(box.rotation.transpose() * box.rotation).isIdentity(1e-9) ||
      box.rotation.determinant() < 0)
    throw InvalidInputError("lattice: the box rotation is not a rotation matrix");
}

}  // namespace

std::vector<Eigen::Vector3d> Lattice::control_points() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(static_cast<std::size_t>(count()));
  for (int k = 0; k < resolution[2]; ++k)
    for (int v = 0; v < resolution[1]; ++v)
      for (int u = 0; u < resolution[0]; ++u) {
        const Eigen::Vector3d t(static_cast<double>(u) / (resolution[0] - 1),
                                static_cast<double>(v) / (resolution[1] - 1),
                                static_cast<double>(k) / (resolution[2] - 1));
        out.push_back(box.origin + box.rotation * t.cwiseProduct(box.size));
      }
  return out;
}

LatticeBox bounding_lattice_box(const mesh::RowMatrixXf<3>& positions, double margin) {
  if (positions.rows() == 0) throw InvalidInputError("lattice box: the mesh has no vertex");
  if (!(margin >= 0) || !std::isfinite(margin))
    throw InvalidInputError("lattice box: the margin must be finite and >= 0");
  const Eigen::Vector3d lo = positions.colwise().minCoeff().transpose().cast<double>();
  const Eigen::Vector3d hi = positions.colwise().maxCoeff().transpose().cast<double>();
  const double grow = margin * (hi - lo).norm();
  LatticeBox box;
  box.origin = lo.array() - grow;
  box.size = (hi - lo).array() + 2 * grow;
  if (!(box.size.array() > 0).all())
    throw InvalidInputError("lattice box: the mesh is flat along an axis; give a margin > 0 or a box");
  return box;
}

FreeFormDeformation::FreeFormDeformation(const mesh::RowMatrixXf<3>& rest, const Lattice& lattice,
                                         const FfdOptions& options)
    : lattice_(lattice), rest_(rest), threads_(options.threads) {
  check_lattice(lattice_);
  for (std::size_t a = 0; a < 3; ++a)
    width_[a] =
        lattice_.basis == LatticeBasis::bernstein ? lattice_.resolution[a] : std::min(4, lattice_.resolution[a]);
  const Eigen::Index n = rest_.rows();
  first_.resize(n, 3);
  basis_.resize(n, width_[0] + width_[1] + width_[2]);
  const Eigen::Matrix3d to_box = lattice_.box.rotation.transpose();
  detail::parallel_for(n, threads_, [&](Eigen::Index begin, Eigen::Index end) {
    std::vector<double> values;
    for (Eigen::Index i = begin; i < end; ++i) {
      const Eigen::Vector3d t =
          (to_box * (rest_.row(i).transpose().cast<double>() - lattice_.box.origin)).cwiseQuotient(lattice_.box.size);
      if (!(t.array() >= -kInsideTolerance).all() || !(t.array() <= 1 + kInsideTolerance).all()) {
        first_.row(i).setConstant(-1);
        continue;
      }
      int column = 0;
      for (std::size_t a = 0; a < 3; ++a) {
        const int l = lattice_.resolution[a];
        values.assign(static_cast<std::size_t>(l), 0.0);
        const double ta = std::clamp(t[static_cast<Eigen::Index>(a)], 0.0, 1.0);
        axis_basis(lattice_, l, ta, values);
        // The window of width_[a] points that holds every nonzero value: the span's four points.
        const int span = std::clamp(static_cast<int>(std::floor(ta * (l - 1))), 0, l - 2);
        const int first = lattice_.basis == LatticeBasis::bernstein ? 0 : std::clamp(span - 1, 0, l - width_[a]);
        first_(i, static_cast<Eigen::Index>(a)) = first;
        for (int j = 0; j < width_[a]; ++j)
          basis_(i, column++) = static_cast<float>(values[static_cast<std::size_t>(first + j)]);
      }
    }
  });
  for (Eigen::Index i = 0; i < n; ++i)
    if (first_(i, 0) < 0) outside_.push_back(static_cast<int>(i));
}

std::vector<std::pair<int, double>> FreeFormDeformation::weights(Eigen::Index i) const {
  std::vector<std::pair<int, double>> out;
  if (first_(i, 0) < 0) return out;
  const float* b0 = &basis_(i, 0);
  const float* b1 = b0 + width_[0];
  const float* b2 = b1 + width_[1];
  for (int k = 0; k < width_[2]; ++k)
    for (int v = 0; v < width_[1]; ++v)
      for (int u = 0; u < width_[0]; ++u) {
        const double w = static_cast<double>(b0[u]) * b1[v] * b2[k];
        if (w != 0) out.emplace_back(lattice_.index(first_(i, 0) + u, first_(i, 1) + v, first_(i, 2) + k), w);
      }
  return out;
}

namespace {

/// Σ_k b2[k] Σ_v b1[v] Σ_u b0[u] table.col(base + u + v·stride_v + k·stride_k): a vertex's window
/// of the lattice, the tensor-product weights of eq. 8 never formed. The B-spline's 4 × 4 × 4
/// window goes 4 u-lanes at a time (the table holds each component contiguous over the control
/// points); other widths take the scalar loops.
template <int N>
Eigen::Matrix<float, N, 1> contract_window(const float* b0, const std::array<int, 3>& width, const FfdTable<N>& table,
                                           int base, int stride_v, int stride_k) noexcept {
  const float* b1 = b0 + width[0];
  const float* b2 = b1 + width[1];
  if (width == std::array<int, 3>{4, 4, 4}) {
    const Eigen::Array4f lanes = Eigen::Map<const Eigen::Array4f>(b0);
    Eigen::Array<float, 4, N> sum = Eigen::Array<float, 4, N>::Zero();
    for (int k = 0; k < 4; ++k)
      for (int v = 0; v < 4; ++v) {
        const Eigen::Array4f w = (b1[v] * b2[k]) * lanes;
        const int row = base + v * stride_v + k * stride_k;
        for (int c = 0; c < N; ++c) sum.col(c) += w * Eigen::Map<const Eigen::Array4f>(&table(c, row));
      }
    return sum.colwise().sum().transpose();
  }
  Eigen::Matrix<float, N, 1> sum = Eigen::Matrix<float, N, 1>::Zero();
  for (int k = 0; k < width[2]; ++k)
    for (int v = 0; v < width[1]; ++v) {
      const int row = base + v * stride_v + k * stride_k;
      for (int u = 0; u < width[0]; ++u) sum += (b0[u] * b1[v] * b2[k]) * table.col(row + u);
    }
  return sum;
}

}  // namespace

template <int N>
Eigen::Matrix<float, N, 1> FreeFormDeformation::contract(Eigen::Index i, const FfdTable<N>& table) const noexcept {
  return contract_window<N>(&basis_(i, 0), width_, table, lattice_.index(first_(i, 0), first_(i, 1), first_(i, 2)),
                            lattice_.resolution[0], lattice_.resolution[0] * lattice_.resolution[1]);
}

template <class Job>
void FreeFormDeformation::frame(std::size_t count, const char* what, mesh::RowMatrixXf<3>& out, Job&& job) const {
  if (static_cast<int>(count) != lattice_.count())
    throw InvalidInputError("ffd: " + std::to_string(count) + " " + what + " given for a lattice of " +
                            std::to_string(lattice_.count()));
  out.resize(rest_.rows(), 3);
  detail::parallel_for(rest_.rows(), threads_, job);
}

void FreeFormDeformation::deform_points(std::span<const Eigen::Vector3d> points, mesh::RowMatrixXf<3>& out) const {
  const std::vector<Eigen::Vector3d> rest = lattice_.control_points();
  FfdTable<3> displacement(3, static_cast<Eigen::Index>(rest.size()));
  for (std::size_t c = 0; c < rest.size() && c < points.size(); ++c)
    displacement.col(static_cast<Eigen::Index>(c)) = (points[c] - rest[c]).cast<float>();
  frame(points.size(), "control points", out, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i) {
      if (first_(i, 0) < 0)
        out.row(i) = rest_.row(i);
      else
        out.row(i) = rest_.row(i) + contract(i, displacement).transpose();
    }
  });
}

void FreeFormDeformation::deform_motors(std::span<const cga::Versor<double>> motors, mesh::RowMatrixXf<3>& out) const {
  FfdTable<detail::kGeneratorSize> logs;
  if (static_cast<int>(motors.size()) == lattice_.count()) detail::fill_log_table(motors, logs);
  // Outside the box the generator is 0, whose exp is exactly the identity.
  using Generator = Eigen::Matrix<float, detail::kGeneratorSize, 1>;
  frame(motors.size(), "control point motors", out, [&](Eigen::Index begin, Eigen::Index end) {
    detail::exp_apply_range(rest_, begin, end, out, [&](Eigen::Index i) -> Generator {
      return first_(i, 0) < 0 ? Generator::Zero() : contract(i, logs);
    });
  });
}

}  // namespace cgamesh::deform
