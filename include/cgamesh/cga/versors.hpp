#pragma once
// Rotors, translators, dilators (paper section 2.4, eq. 8-14) and the sandwich product.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::cga {

template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

namespace detail {
template <class T>
void require_finite(const Vec3<T>& v, const char* what) {
  if (!v.allFinite()) throw InvalidInputError(std::string(what) + " has a NaN or infinite component");
}
template <class T>
void require_finite(T v, const char* what) {
  if (!std::isfinite(v)) throw InvalidInputError(std::string(what) + " is NaN or infinite");
}
/// Mask of every blade whose grade occurs in M: what a sandwich of M can produce.
[[nodiscard]] constexpr BladeMask grades_of(BladeMask m) noexcept {
  BladeMask out = 0;
  for (unsigned g = 0; g <= kDimension; ++g)
    if ((m & grade_mask(g)) != 0) out |= grade_mask(g);
  return out;
}
}  // namespace detail

/// Rotor of a rotation by `angle` radians about the unit `axis`, right-handed (eq. 8):
/// R = cos(angle/2) - sin(angle/2) u I3, with I3 = e1 e2 e3. A rotation about +e3 by +90deg
/// takes e1 to e2.
/// @param[in] axis   rotation axis (any non-zero length; it is normalised)
/// @param[in] angle  radians
/// @throws InvalidInputError for a zero or non-finite axis, or a non-finite angle.
template <class T>
[[nodiscard]] Rotor<T> rotor(const Vec3<T>& axis, T angle) {
  detail::require_finite(axis, "rotor axis");
  detail::require_finite(angle, "rotor angle");
  const T n = axis.norm();
  if (!(n > T(0))) throw InvalidInputError("rotor: the rotation axis is the zero vector");
  const Vec3<T> u = axis / n;
  const T c = std::cos(angle / 2), s = std::sin(angle / 2);
  // u I3 = u1 e23 - u2 e13 + u3 e12.
  return Rotor<T>({c, -s * u.z(), s * u.y(), -s * u.x()});
}

/// Translator by t (eq. 10): T = 1 - (1/2) t einf.
template <class T>
[[nodiscard]] constexpr Translator<T> translator(const Vec3<T>& t) noexcept {
  return Translator<T>({T(1), T(-0.5) * t.x(), T(-0.5) * t.y(), T(-0.5) * t.z()});
}

/// Dilator scaling by s > 0 about the origin (eq. 12), normalised so that D ~D = 1:
/// D = ((1 + s) + (1 - s) einf^eo) / (2 sqrt(s)), the multiple of eq. (12) with unit norm.
/// @throws InvalidInputError when s is not a finite positive number.
template <class T>
[[nodiscard]] Dilator<T> dilator(T s) {
  detail::require_finite(s, "dilation factor");
  if (!(s > T(0))) throw InvalidInputError("dilator: the scale factor must be > 0, got " + std::to_string(s));
  const T k = T(1) / (T(2) * std::sqrt(s));
  return Dilator<T>({(T(1) + s) * k, (T(1) - s) * k});
}

/// The versor of x -> s R(x) + t: translation * rotation * dilation (applied right to left).
template <class T>
[[nodiscard]] Versor<T> similarity(const Vec3<T>& t, const Rotor<T>& r, T s) {
  return Versor<T>(translator(t) * r * dilator(s));
}

/// Sandwich O' = V O V^-1 (eq. 14) for any object O (point, sphere, plane, line, circle, ...),
/// keeping the grades of O (a versor maps each grade to itself).
/// @param[in] v  versor; must be invertible
/// @param[in] o  object
/// @throws InvalidInputError when v is not invertible.
template <class T, BladeMask V, BladeMask O>
[[nodiscard]] Multivector<T, detail::grades_of(O)> sandwich(const Multivector<T, V>& v, const Multivector<T, O>& o) {
  return project<detail::grades_of(O)>(product_part<detail::grades_of(O)>(v * o, versor_inverse(v)));
}

/// Sandwich V O ~V for a unit versor (V ~V = 1), skipping the normalisation of versor_inverse.
template <class T, BladeMask V, BladeMask O>
[[nodiscard]] constexpr Multivector<T, detail::grades_of(O)> unit_sandwich(const Multivector<T, V>& v,
                                                                          const Multivector<T, O>& o) noexcept {
  return project<detail::grades_of(O)>(product_part<detail::grades_of(O)>(v * o, reverse(v)));
}

/// The parts of a similarity x -> scale * R(x) + translation.
template <class T>
struct SimilarityParts {
  Vec3<T> translation;
  Rotor<T> rotation;  ///< unit rotor
  T scale;
};

/// Splits a unit motor M = T(t) R into its translation and unit rotor.
/// @throws InvalidInputError when M has no rotation part (not a motor).
template <class T>
[[nodiscard]] SimilarityParts<T> decompose(const Motor<T>& m) {
  const Rotor<T> r = project<mask::rotor>(m);
  const T rn = norm(r);
  if (!(rn > T(0)) || !std::isfinite(rn))
    throw InvalidInputError("decompose: the versor has no rotation part (it is not a rigid motion or similarity)");
  const Rotor<T> ru = r / rn;
  const Translator<T> tr = project<mask::translator>(m * reverse(ru)) / rn;
  return {T(-2) * Vec3<T>(tr[1], tr[2], tr[3]), ru, T(1)};
}

/// Splits a TRS versor V = T(t) R D(s) (any positive multiple) into translation, unit rotor
/// and scale.
/// @throws InvalidInputError when V is not the versor of a similarity.
template <class T>
[[nodiscard]] SimilarityParts<T> decompose(const Versor<T>& v_in) {
  const T n = norm_squared(v_in);
  if (!(n > T(0)) || !std::isfinite(n))
    throw InvalidInputError("decompose: <V ~V> = " + std::to_string(n) + " is not positive: not a TRS versor");
  const Versor<T> v = v_in / std::sqrt(n);
  // D(s) scales einf by s while T and R fix it: V einf ~V = s einf.
  const Vector<T> inf_image = unit_sandwich(v, einf<T>());
  const T s = inf_image.template get<blade::einf>();
  if (!(s > T(0)) || !std::isfinite(s))
    throw InvalidInputError("decompose: the versor does not map infinity to itself: not a similarity");
  // Any other component of V einf ~V (e.g. from a transversion 1 + t ^ eo) moves infinity.
  if (max_abs(Vector<T>(inf_image - einf<T>() * s)) >
      std::sqrt(std::numeric_limits<T>::epsilon()) * std::max(s, max_abs(v) * max_abs(v)))
    throw InvalidInputError("decompose: the versor does not map infinity to itself: not a similarity");
  SimilarityParts<T> parts = decompose(Motor<T>(project<mask::motor>(v * reverse(dilator(s)))));
  parts.scale = s;
  return parts;
}

}  // namespace cgamesh::cga
