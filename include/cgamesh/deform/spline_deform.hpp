#pragma once
// Spline-aligned deformation (paper section III): key motors R_1..R_n, a harmonic parameter
// lambda in [0, 1] per vertex (0 on the start handle H_1, 1 on the end handle H_n, section
// III.A), and the motor field S(lambda) = exp(sum_j W_j(lambda) log R_j) (eq. 1), bound and
// deformed as in eq. (2) (deform/motor_blend.hpp).

#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "cgamesh/deform/harmonic_field.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::deform {

enum class SplineBasis {
  linear,              ///< piecewise linear through the n keys, uniformly spaced (n = 2: Fig. 2)
  quadratic_lagrange,  ///< n = 3: w1 = 2l^2 - 3l + 1, w2 = -4l^2 + 4l, w3 = 2l^2 - l (III.B)
  bezier,              ///< Bernstein polynomials of degree n - 1 (n = 4: cubic Bezier)
  bspline,             ///< clamped uniform B-spline of `degree`, n >= degree + 1 (Fig. 4, III.C)
};

struct SplineOptions {
  SplineBasis basis = SplineBasis::bspline;
  int degree = 3;  ///< B-spline degree (>= 1); other bases ignore it
  HarmonicOptions harmonic;
  /// A mesh with more vertices than this has its parameter λ rounded to `levels` evenly spaced
  /// values (0 and 1 exactly among them), so a frame computes `levels` motors and then costs a
  /// table lookup per vertex; 16384 levels move λ by at most 3·10⁻⁵. 0: a motor per vertex.
  int levels = 16384;
};

/// Basis weights W_j(lambda) of n keys. Every basis interpolates the end keys (S(0) = R_1,
/// S(1) = R_n) and sums to 1; lambda is clamped to [0, 1].
/// @param[in]  lambda  parameter
/// @param[out] out     #n weights
/// @throws InvalidInputError when the basis does not take n keys (linear, bezier: n >= 2;
///         quadratic_lagrange: n = 3; bspline: n >= degree + 1, degree >= 1) or lambda is NaN.
void spline_weights(const SplineOptions& options, double lambda, std::span<double> out);

/// The harmonic parameter lambda: 0 on `start`, 1 on `end` (section III.A, VIII).
/// @return #V values in [0, 1] (mean-value weights)
/// @throws as harmonic_precompute(); InvalidInputError when a handle is empty or they overlap.
[[nodiscard]] Eigen::VectorXd spline_parameter(const mesh::Mesh& mesh, std::span<const int> start,
                                               std::span<const int> end, const HarmonicOptions& options = {});

/// Binds the mesh to the key motors along the harmonic parameter from `start` to `end`.
/// @param[in] rest_keys  #n key versors at rest
/// @throws as spline_parameter(), spline_weights() and MotorBlend.
[[nodiscard]] MotorBlend bind_spline(const mesh::Mesh& mesh, std::span<const int> start, std::span<const int> end,
                                     std::span<const cga::Versor<double>> rest_keys, const SplineOptions& options = {},
                                     const MotorBlendOptions& blend_options = {});

}  // namespace cgamesh::deform
