#pragma once
// Least-squares B-spline fitting of motors (paper section III.C, eq. 3-5): control versors
// R_0..R_m with Q_i ~ exp(sum_j N_j(lambda_i) log R_j), solved on the bivector (log)
// components as A^T A log R = A^T log Q: Cholesky when A^T A is well conditioned, SVD of A
// otherwise. Logs carry seven components, the paper's six plus the dilation einf^eo, so
// dilating keys fit too (motors keep it 0).

#include <cstddef>
#include <span>
#include <vector>

#include "cgamesh/cga/multivector.hpp"

namespace cgamesh::deform {

struct BsplineFitOptions {
  int degree = 3;                ///< clamped uniform B-spline degree (spline_weights, bspline)
  double max_condition = 1e10;   ///< above this condition number of A^T A, solve by SVD
};

struct BsplineFit {
  std::vector<cga::Versor<double>> control;  ///< #m control versors R_j
  double rms_residual = 0;  ///< sqrt(mean_i |A log R - log Q|_i^2), in log (bivector) space
  double max_residual = 0;  ///< max_i of the same per-key norm
  bool used_svd = false;    ///< A^T A was singular or ill-conditioned
};

/// Fits `control_count` control versors to key versors at parameters (eq. 5).
/// @param[in] keys           #k key versors Q_i (TRS; their principal logs are fitted)
/// @param[in] parameters     #k parameters lambda_i in [0, 1]
/// @param[in] control_count  m >= degree + 1
/// @throws InvalidInputError when keys and parameters differ in size or are empty, a
///         parameter is not finite, control_count is too small, or a key has no log.
[[nodiscard]] BsplineFit fit_bspline_motors(std::span<const cga::Versor<double>> keys,
                                            std::span<const double> parameters, std::size_t control_count,
                                            const BsplineFitOptions& options = {});

}  // namespace cgamesh::deform
