#include "cgamesh/deform/spline_deform.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cgamesh/deform/harmonic_handles.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::deform {
namespace {

/// Clamped uniform B-spline basis of degree d at t in [0, 1] (The NURBS Book, A2.2).
void bspline_basis(int d, double t, std::span<double> out) {
  const int n = static_cast<int>(out.size());
  const int spans = n - d;  // knot intervals of [0, 1]
  const auto knot = [&](int i) { return std::clamp(static_cast<double>(i - d) / spans, 0.0, 1.0); };
  // Interval k with knot(k) <= t < knot(k + 1); t = 1 belongs to the last one.
  const int k = std::min(d + static_cast<int>(std::floor(t * spans)), n - 1);
  const auto size = static_cast<std::size_t>(d + 1);
  std::vector<double> basis(size, 0.0), left(size, 0.0), right(size, 0.0);  // basis: N_{k-d..k}
  basis[0] = 1.0;
  for (std::size_t j = 1; j < size; ++j) {
    left[j] = t - knot(k + 1 - static_cast<int>(j));
    right[j] = knot(k + static_cast<int>(j)) - t;
    double saved = 0.0;
    for (std::size_t r = 0; r < j; ++r) {
      const double temp = basis[r] / (right[r + 1] + left[j - r]);
      basis[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    basis[j] = saved;
  }
  std::fill(out.begin(), out.end(), 0.0);
  std::copy(basis.begin(), basis.end(), out.begin() + (k - d));
}

}  // namespace

void spline_weights(const SplineOptions& options, double lambda, std::span<double> out) {
  if (std::isnan(lambda)) throw InvalidInputError("spline weights: lambda is NaN");
  const double t = std::clamp(lambda, 0.0, 1.0);
  const std::size_t n = out.size();
  const auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw InvalidInputError("spline basis: " + what + ", got " + std::to_string(n) + " key motors");
  };
  switch (options.basis) {
    case SplineBasis::linear:
      require(n >= 2, "linear needs at least 2 key motors");
      bspline_basis(1, t, out);
      return;
    case SplineBasis::quadratic_lagrange:
      require(n == 3, "quadratic_lagrange needs exactly 3 key motors");
      out[0] = 2 * t * t - 3 * t + 1;
      out[1] = -4 * t * t + 4 * t;
      out[2] = 2 * t * t - t;
      return;
    case SplineBasis::bezier: {
      require(n >= 2, "bezier needs at least 2 key motors");
      const int d = static_cast<int>(n) - 1;
      double binomial = 1;
      for (int j = 0; j <= d; ++j) {
        out[static_cast<std::size_t>(j)] = binomial * std::pow(t, j) * std::pow(1 - t, d - j);
        binomial = binomial * (d - j) / (j + 1);
      }
      return;
    }
    case SplineBasis::bspline:
      if (options.degree < 1) throw InvalidInputError("spline basis: the B-spline degree must be >= 1");
      require(static_cast<int>(n) >= options.degree + 1, "a B-spline of degree " + std::to_string(options.degree) +
                                                             " needs at least " + std::to_string(options.degree + 1) +
                                                             " key motors");
      bspline_basis(options.degree, t, out);
      return;
  }
  throw InvalidInputError("spline weights: unknown basis");
}

Eigen::VectorXd spline_parameter(const mesh::Mesh& mesh, std::span<const int> start, std::span<const int> end,
                                 const HarmonicOptions& options) {
  const std::vector<std::vector<int>> handles{{start.begin(), start.end()}, {end.begin(), end.end()}};
  return harmonic_coordinates(mesh, handles, options).col(1);
}

MotorBlend bind_spline(const mesh::Mesh& mesh, std::span<const int> start, std::span<const int> end,
                       std::span<const cga::Versor<double>> rest_keys, const SplineOptions& options,
                       const MotorBlendOptions& blend_options) {
  if (options.levels < 0 || options.levels == 1) throw InvalidInputError("spline: levels must be 0 or >= 2");
  const Eigen::VectorXd lambda = spline_parameter(mesh, start, end, options.harmonic);
  const auto n = static_cast<Eigen::Index>(rest_keys.size());
  if (options.levels == 0 || lambda.size() <= options.levels) {
    WeightMatrix weights(lambda.size(), n);
    for (Eigen::Index i = 0; i < lambda.size(); ++i)
      spline_weights(options, lambda[i], std::span<double>(weights.row(i).data(), rest_keys.size()));
    return MotorBlend(mesh.positions, std::move(weights), rest_keys, blend_options);
  }
  const int top = options.levels - 1;
  WeightMatrix weights(options.levels, n);
  for (int r = 0; r <= top; ++r)
    spline_weights(options, static_cast<double>(r) / top, std::span<double>(weights.row(r).data(), rest_keys.size()));
  std::vector<int> rows(static_cast<std::size_t>(lambda.size()));
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    rows[static_cast<std::size_t>(i)] = static_cast<int>(std::lround(std::clamp(lambda[i], 0.0, 1.0) * top));
  return MotorBlend(mesh.positions, std::move(weights), std::move(rows), rest_keys, blend_options);
}

}  // namespace cgamesh::deform
