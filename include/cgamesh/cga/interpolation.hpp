#pragma once
// Interpolation of versors (paper section 2.5): linear and logarithmic blends, and the n-way
// blend exp(sum w_j log V_j) used by the motor-handle deformations.

#include <cmath>
#include <complex>
#include <cstddef>
#include <span>
#include <string>

#include "cgamesh/cga/exp_log.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::cga {

/// Linear blend (1 - alpha) a + alpha b (the paper's choice for generated keyframes).
template <class T, BladeMask M>
[[nodiscard]] constexpr Multivector<T, M> lerp(const Multivector<T, M>& a, const Multivector<T, M>& b,
                                               T alpha) noexcept {
  return (T(1) - alpha) * a + alpha * b;
}

/// (V ~V)^(-1/2) V for an even multivector V: the nearest unit versor along the ray of V.
/// V ~V = a + Q with Q a 4-vector whose square q is a scalar, so the inverse square root is
/// alpha + beta Q, computed from the two "eigenvalues" a +- sqrt(q).
/// @throws InvalidInputError when <V ~V>_0 <= 0 (V is not a blend of proper versors).
template <class T, BladeMask M>
[[nodiscard]] Multivector<T, M> normalized(const Multivector<T, M>& v) {
  static_assert((M & ~kEvenBlades) == 0, "normalized() takes even multivectors (rotors, motors, versors)");
  const auto n = v * reverse(v);
  const T a = scalar_part(n);
  if (!(a > T(0)) || !std::isfinite(a))
    throw InvalidInputError("normalized: <V ~V> = " + std::to_string(a) + " is not positive; cannot normalise");
  const auto q4 = grade_part<4>(n);
  const T q = scalar_product(q4, q4);
  T alpha, beta;
  if (std::abs(q) < T(1e-8) * a * a) {
    // Series of x^(-1/2) about a, to second order in q.
    alpha = T(1) / std::sqrt(a) + T(3) / T(8) * q / (a * a * std::sqrt(a));
    beta = -T(0.5) / (a * std::sqrt(a)) - T(15) / T(48) * q / (a * a * a * std::sqrt(a));
  } else {
    const std::complex<T> r = std::sqrt(std::complex<T>(q));
    const std::complex<T> fp = T(1) / std::sqrt(a + r), fm = T(1) / std::sqrt(a - r);
    alpha = ((fp + fm) / T(2)).real();
    beta = ((fp - fm) / (T(2) * r)).real();
  }
  // (alpha + beta Q) on the left: N ~N = (a + Q)^(-1/2) V ~V (a + Q)^(-1/2) = 1. (On the right,
  // V (a + Q)^(-1) ~V is 1 only when Q commutes with V, as for motors but not TRS versors.)
  return project<M>(v * alpha + q4 * v * beta);
}

/// Linear blend renormalised to a unit versor.
template <class T, BladeMask M>
[[nodiscard]] Multivector<T, M> lerp_normalized(const Multivector<T, M>& a, const Multivector<T, M>& b, T alpha) {
  return normalized(lerp(a, b, alpha));
}

/// Logarithmic blend a exp(alpha log(a^-1 b)) (the paper's choice for file keyframes), for
/// unit rotors, motors and TRS versors. Symmetric: log_blend(a, b, t) = log_blend(b, a, 1 - t).
/// @throws InvalidInputError when a or b is not a unit versor of its kind.
template <class T, BladeMask M>
[[nodiscard]] Multivector<T, M> log_blend(const Multivector<T, M>& a, const Multivector<T, M>& b, T alpha) {
  const Multivector<T, M> rel = project<M>(reverse(a) * b);
  return project<M>(a * exp(log(rel) * alpha));
}

/// n-way blend exp(sum_j w_j log V_j) of unit rotors, motors or TRS versors.
/// @param[in] versors  #n versors
/// @param[in] weights  #n weights (not required to sum to 1)
/// @throws InvalidInputError when the spans differ in size or are empty, or a versor has no log.
template <class T, BladeMask M>
[[nodiscard]] Multivector<T, M> blend(std::span<const Multivector<T, M>> versors, std::span<const T> weights) {
  if (versors.size() != weights.size() || versors.empty())
    throw InvalidInputError("blend: need as many weights as versors, and at least one (got " +
                            std::to_string(versors.size()) + " versors, " + std::to_string(weights.size()) +
                            " weights)");
  auto sum = log(versors[0]) * weights[0];
  for (std::size_t j = 1; j < versors.size(); ++j) sum += log(versors[j]) * weights[j];
  return project<M>(exp(sum));
}

}  // namespace cgamesh::cga
