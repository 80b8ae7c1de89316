#pragma once
// Exponential and logarithm of versors (paper section 2.5), in closed form.
//
// The versors of similarities x -> s R x + t are exp(B) of the 7-dimensional bivectors
//     B = Br + Bt + Bd,   Br in span(e12, e13, e23), Bt = -(1/2) v ^ einf, Bd = -(lambda/2) einf^eo
// where exp(Br) is the rotor of the rotation vector w = 2 (-B23, B13, -B12), v is the
// translational velocity and s = e^lambda. Their flow is x' = A x + v with A = lambda Id + [w]x,
// so exp(B) = T(t) R D(s) with t = F(A) v, F(A) = sum A^k / (k+1)! = (e^A - Id) A^-1.
// F(A) acts on the axis of w as f(lambda) and on the plane of w as the complex number
// f(lambda + i phi), phi = |w|, with f(z) = (e^z - 1)/z: no case split for pure translations,
// pure rotations or screws, and no NaN at the identity.

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::cga {

namespace mask {
inline constexpr BladeMask rotation_generator = (1u << blade::e12) | (1u << blade::e13) | (1u << blade::e23);
inline constexpr BladeMask motor_generator =
    rotation_generator | (1u << blade::e1inf) | (1u << blade::e2inf) | (1u << blade::e3inf);
inline constexpr BladeMask similarity_generator = motor_generator | (1u << blade::info);
}  // namespace mask

/// Bivector generating a rotation: log of a Rotor.
template <class T> using RotationGenerator = Multivector<T, mask::rotation_generator>;
/// Bivector generating a rigid motion (screw): log of a Motor.
template <class T> using MotorGenerator = Multivector<T, mask::motor_generator>;
/// Bivector generating a similarity: log of a TRS Versor.
template <class T> using SimilarityGenerator = Multivector<T, mask::similarity_generator>;

namespace detail {

/// f(z) = (e^z - 1) / z, accurate near z = 0.
template <class C>
[[nodiscard]] C expm1_over_z(C z) noexcept {
  using std::abs;
  if (abs(z) < 0.1) {
    // Taylor series sum z^k / (k+1)!; 11 terms reach double precision for |z| < 0.1.
    C sum(1), term(1);
    for (int k = 1; k <= 11; ++k) {
      term *= z / static_cast<typename C::value_type>(k + 1);
      sum += term;
    }
    return sum;
  }
  return (std::exp(z) - C(1)) / z;
}

/// Coefficients (c1, c2, c3) of h(A) v = c1 v + c2 w (w . v) + c3 (w x v) for A = lambda Id + [w]x,
/// given h on the axis (h_axis = h(lambda)) and on the plane (h_plane = h(lambda + i phi)).
template <class T>
struct ScrewCoefficients {
  T c1, c2, c3;
};
template <class T>
[[nodiscard]] ScrewCoefficients<T> screw_coefficients(T h_axis, std::complex<T> h_plane, T phi) noexcept {
  if (!(phi > T(0))) return {h_axis, T(0), T(0)};
  // For small phi c2 and c3 lose digits, but they multiply terms of order phi^2 and phi.
  return {h_plane.real(), (h_axis - h_plane.real()) / (phi * phi), h_plane.imag() / phi};
}

template <class T>
[[nodiscard]] Vec3<T> apply_screw(const ScrewCoefficients<T>& c, const Vec3<T>& w, const Vec3<T>& v) noexcept {
  return c.c1 * v + c.c2 * w.dot(v) * w + c.c3 * w.cross(v);
}

/// Rotation vector w of a rotation generator Br (exp(Br) rotates by |w| about w / |w|).
template <class T, BladeMask M>
[[nodiscard]] Vec3<T> rotation_vector(const Multivector<T, M>& b) noexcept {
  return T(2) * Vec3<T>(-b.template get<blade::e23>(), b.template get<blade::e13>(), -b.template get<blade::e12>());
}

/// The motor part T(F(A) v) R of exp(B).
template <class T, BladeMask M>
[[nodiscard]] Motor<T> exp_motor_part(const Multivector<T, M>& b, T lambda) noexcept {
  const T b12 = b.template get<blade::e12>(), b13 = b.template get<blade::e13>(), b23 = b.template get<blade::e23>();
  const T theta = std::sqrt(b12 * b12 + b13 * b13 + b23 * b23);  // half the rotation angle
  const T sinc = theta < T(1e-4) ? T(1) - theta * theta / T(6) : std::sin(theta) / theta;
  const Rotor<T> r({std::cos(theta), sinc * b12, sinc * b13, sinc * b23});
  const Vec3<T> w = rotation_vector(b);
  const Vec3<T> v = T(-2) * Vec3<T>(b.template get<blade::e1inf>(), b.template get<blade::e2inf>(),
                                    b.template get<blade::e3inf>());
  const T phi = T(2) * theta;
  const auto c = screw_coefficients(expm1_over_z(std::complex<T>(lambda)).real(),
                                    expm1_over_z(std::complex<T>(lambda, phi)), phi);
  return translator(apply_screw(c, w, v)) * r;
}

/// Log of the similarity with the given parts, for dilation lambda = log(scale).
template <class T>
[[nodiscard]] MotorGenerator<T> log_parts(const SimilarityParts<T>& p, T lambda) noexcept {
  const Rotor<T>& ru = p.rotation;
  // Principal rotation angle 2 theta in [0, 2 pi): exp(log(M)) = M, sign included.
  const T s = std::sqrt(ru[1] * ru[1] + ru[2] * ru[2] + ru[3] * ru[3]);
  const T theta = std::atan2(s, ru[0]);
  const T k = (s < T(1e-4) && ru[0] > 0) ? T(1) + s * s / T(6) : theta / s;
  const RotationGenerator<T> br({k * ru[1], k * ru[2], k * ru[3]});
  const Vec3<T> w = rotation_vector(br);
  const T phi = T(2) * theta;
  // Invert F(A): the same structure with 1/f.
  const auto c = screw_coefficients(T(1) / expm1_over_z(std::complex<T>(lambda)).real(),
                                    T(1) / expm1_over_z(std::complex<T>(lambda, phi)), phi);
  const Vec3<T> v = apply_screw(c, w, p.translation);
  return MotorGenerator<T>({br[0], br[1], br[2], T(-0.5) * v.x(), T(-0.5) * v.y(), T(-0.5) * v.z()});
}

template <class T, BladeMask M>
void require_unit(const Multivector<T, M>& v, const char* what) {
  const T n = norm_squared(v);
  if (!std::isfinite(n) || std::abs(n - T(1)) > std::sqrt(std::numeric_limits<T>::epsilon()) * T(16))
    throw InvalidInputError(std::string("log: the ") + what + " is not normalised (<V ~V> = " + std::to_string(n) +
                            "); normalise it first");
}

}  // namespace detail

/// Rotor exp(Br) (eq. 8 with Br = -u I3 angle/2).
template <class T>
[[nodiscard]] Rotor<T> exp(const RotationGenerator<T>& b) noexcept {
  return project<mask::rotor>(detail::exp_motor_part(b, T(0)));
}
/// Motor exp(B) of a screw generator: rotation, translation or both.
template <class T>
[[nodiscard]] Motor<T> exp(const MotorGenerator<T>& b) noexcept {
  return detail::exp_motor_part(b, T(0));
}
/// TRS versor exp(B) of a similarity generator: T(t) R D(s) with s = exp(-2 B_{einf^eo}).
template <class T>
[[nodiscard]] Versor<T> exp(const SimilarityGenerator<T>& b) noexcept {
  const T half = -b.template get<blade::info>();  // lambda / 2
  const Dilator<T> d({std::cosh(half), -std::sinh(half)});
  return Versor<T>(detail::exp_motor_part(b, T(2) * half) * d);
}

/// exp of any bivector of G(4,1), in closed form by its invariant decomposition
/// (Roelfs & De Keninck): B = B1 + B2 with B1, B2 commuting and Bi^2 = li scalars, the roots of
/// l^2 - <B^2>_0 l + (B^B)^2 / 4 = 0, B1 = (l1 B - (B^B) B / 2) / (l1 - l2); then
/// exp(B) = exp(B1) exp(B2), each a cos/cosh/1 + Bi closed form. When l1 and l2 (nearly)
/// coincide the split is ill-conditioned and the Taylor series is used instead.
template <class T>
[[nodiscard]] Versor<T> exp(const Bivector<T>& b) {
  const auto sq = b * b;
  const T s = scalar_part(sq);
  const auto w4 = grade_part<4>(sq);  // B ^ B
  const T p = scalar_product(w4, w4);
  const T root = std::sqrt(std::max(s * s - p, T(0)));
  const T l1 = (s + root) / T(2), l2 = (s - root) / T(2);
  const T size = std::abs(l1) + std::abs(l2) + T(1);
  if (!(root > T(1e-4) * size)) return project<mask::versor>(exp_series(b));
  const Bivector<T> b1 = (l1 * b - grade_part<2>(w4 * b) / T(2)) / (l1 - l2);
  const Bivector<T> b2 = b - b1;
  const auto simple_exp = [](const Bivector<T>& bi, T li) {
    const T r = std::sqrt(std::abs(li));
    T c = T(1), k = T(1);
    if (li < T(0)) c = std::cos(r), k = std::sin(r) / r;
    else if (li > T(0)) c = std::cosh(r), k = std::sinh(r) / r;
    return Scalar<T>({c}) + bi * k;
  };
  return project<mask::versor>(simple_exp(b1, l1) * simple_exp(b2, l2));
}

/// Principal logarithm of a unit rotor: rotation angle in [0, 2 pi).
/// @throws InvalidInputError when R ~R != 1.
template <class T>
[[nodiscard]] RotationGenerator<T> log(const Rotor<T>& r) {
  detail::require_unit(r, "rotor");
  return project<mask::rotation_generator>(detail::log_parts(SimilarityParts<T>{Vec3<T>::Zero(), r, T(1)}, T(0)));
}
/// Logarithm of a unit motor T(t) R: exp(log(M)) = M for rotation angles in [0, 2 pi); works
/// for pure translations (no NaN), pure rotations, screws, and at the identity.
/// @throws InvalidInputError when M ~M != 1.
template <class T>
[[nodiscard]] MotorGenerator<T> log(const Motor<T>& m) {
  detail::require_unit(m, "motor");
  return detail::log_parts(decompose(m), T(0));
}
/// Logarithm of a TRS versor V = T(t) R D(s), any positive multiple (the scalar factor is
/// discarded: V and kV are the same transformation).
/// @throws InvalidInputError when V is not the versor of a similarity x -> s R x + t.
template <class T>
[[nodiscard]] SimilarityGenerator<T> log(const Versor<T>& v) {
  const SimilarityParts<T> p = decompose(v);
  const T lambda = std::log(p.scale);
  SimilarityGenerator<T> out(detail::log_parts(p, lambda));
  out.template at<blade::info>() = -lambda / T(2);
  return out;
}

/// exp of any multivector by its Taylor series with scaling and squaring: the reference the
/// closed forms are tested against (the seed implementation's method).
template <class T, BladeMask M>
[[nodiscard]] Dense<T> exp_series(const Multivector<T, M>& a) noexcept {
  Dense<T> x(a);
  int squarings = 0;
  for (T m = max_abs(x); m > T(0.125); m /= 2) ++squarings;
  x /= std::ldexp(T(1), squarings);
  Dense<T> sum(basis_blade<T, blade::scalar>());
  Dense<T> term = sum;
  for (int k = 1; k <= 24; ++k) {
    term = term * x / T(k);
    sum += term;
  }
  for (int i = 0; i < squarings; ++i) sum = sum * sum;
  return sum;
}

/// log of a multivector near 1 by the series log(1 + x) = x - x^2/2 + x^3/3 - ...
/// @throws InvalidInputError when |a - 1| (largest coefficient) is not below 1/2;
///         SolverError when the series does not converge.
template <class T, BladeMask M>
[[nodiscard]] Dense<T> log_series(const Multivector<T, M>& a) {
  const Dense<T> x = Dense<T>(a) - Dense<T>(basis_blade<T, blade::scalar>());
  if (!(max_abs(x) < T(0.5)))
    throw InvalidInputError("log_series: the series only converges near 1; the argument is too far from it");
  Dense<T> sum, power(basis_blade<T, blade::scalar>());
  for (int k = 1; k <= 400; ++k) {
    power = power * x;
    sum += power * (T(k % 2 == 1 ? 1 : -1) / T(k));
    if (max_abs(power) < std::numeric_limits<T>::epsilon() * T(1e-2)) return sum;
  }
  throw SolverError("log_series: the series did not converge (the argument is too far from 1)");
}

}  // namespace cgamesh::cga
