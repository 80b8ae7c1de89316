#include "cgamesh/deform/bspline_fit.hpp"

#include <cmath>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "cgamesh/cga/exp_log.hpp"
#include "cgamesh/deform/spline_deform.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::deform {

BsplineFit fit_bspline_motors(std::span<const cga::Versor<double>> keys, std::span<const double> parameters,
                              std::size_t control_count, const BsplineFitOptions& options) {
  using Generator = cga::SimilarityGenerator<double>;
  constexpr Eigen::Index kComponents = Generator::size;
  if (keys.empty() || keys.size() != parameters.size())
    throw InvalidInputError("B-spline fit: need as many parameters as keys, and at least one key (got " +
                            std::to_string(keys.size()) + " keys, " + std::to_string(parameters.size()) +
                            " parameters)");
  const SplineOptions basis{SplineBasis::bspline, options.degree, {}};
  const auto k = static_cast<Eigen::Index>(keys.size()), m = static_cast<Eigen::Index>(control_count);
  Eigen::MatrixXd a(k, m), q(k, kComponents);
  for (Eigen::Index i = 0; i < k; ++i) {
    const double t = parameters[static_cast<std::size_t>(i)];
    if (!std::isfinite(t)) throw InvalidInputError("B-spline fit: parameter " + std::to_string(i) + " is not finite");
    Eigen::RowVectorXd row(m);
    spline_weights(basis, t, std::span<double>(row.data(), control_count));
    a.row(i) = row;
    const Generator g = cga::log(keys[static_cast<std::size_t>(i)]);
    for (Eigen::Index c = 0; c < kComponents; ++c) q(i, c) = g[static_cast<std::size_t>(c)];
  }

  BsplineFit fit;
  const Eigen::MatrixXd ata = a.transpose() * a;
  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(ata, Eigen::EigenvaluesOnly).eigenvalues();
  const bool well_conditioned =
      eigenvalues.minCoeff() > 0 && eigenvalues.maxCoeff() / eigenvalues.minCoeff() <= options.max_condition;
  Eigen::MatrixXd r;
  if (well_conditioned) {
    r = ata.llt().solve(a.transpose() * q);
  } else {
    fit.used_svd = true;
    r = Eigen::JacobiSVD<Eigen::MatrixXd>(a, Eigen::ComputeThinU | Eigen::ComputeThinV).solve(q);
  }
  const Eigen::VectorXd residual = (a * r - q).rowwise().norm();
  fit.rms_residual = std::sqrt(residual.squaredNorm() / static_cast<double>(k));
  fit.max_residual = residual.maxCoeff();
  fit.control.reserve(control_count);
  for (Eigen::Index j = 0; j < m; ++j) {
    Generator g;
    for (Eigen::Index c = 0; c < kComponents; ++c) g[static_cast<std::size_t>(c)] = r(j, c);
    fit.control.push_back(cga::exp(g));
  }
  return fit;
}

}  // namespace cgamesh::deform
