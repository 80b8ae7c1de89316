#pragma once
// Unary operations of G(4,1): reverse, grade involution, Clifford conjugate, grade projection,
// dual and undual (eq. 6-7), norms and inverses.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include "cgamesh/cga/blade.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::cga {

namespace detail {
/// Multiplies each grade g of a by Signs[g].
template <std::array<int, 6> Signs, class T, BladeMask M>
[[nodiscard]] constexpr Multivector<T, M> grade_signs(Multivector<T, M> a) noexcept {
  for (std::size_t i = 0; i < Multivector<T, M>::size; ++i)
    if (Signs[grade(Multivector<T, M>::blades[i])] < 0) a[i] = -a[i];
  return a;
}
}  // namespace detail

/// Reverse ~a: grades 2 and 3 change sign.
template <class T, BladeMask M>
[[nodiscard]] constexpr Multivector<T, M> reverse(const Multivector<T, M>& a) noexcept {
  return detail::grade_signs<std::array<int, 6>{1, 1, -1, -1, 1, 1}>(a);
}
/// Grade involution: odd grades change sign.
template <class T, BladeMask M>
[[nodiscard]] constexpr Multivector<T, M> involution(const Multivector<T, M>& a) noexcept {
  return detail::grade_signs<std::array<int, 6>{1, -1, 1, -1, 1, -1}>(a);
}
/// Clifford conjugate (reverse of the involution): grades 1, 2 and 5 change sign.
template <class T, BladeMask M>
[[nodiscard]] constexpr Multivector<T, M> conjugate(const Multivector<T, M>& a) noexcept {
  return detail::grade_signs<std::array<int, 6>{1, -1, -1, 1, 1, -1}>(a);
}

/// The grade-G part of a, typed to hold only the blades of that grade that a can have.
template <unsigned G, class T, BladeMask M>
[[nodiscard]] constexpr auto grade_part(const Multivector<T, M>& a) noexcept {
  return project<M & grade_mask(G)>(a);
}
/// The scalar part <a>_0 as a number.
template <class T, BladeMask M>
[[nodiscard]] constexpr T scalar_part(const Multivector<T, M>& a) noexcept {
  return a.template get<blade::scalar>();
}

/// The pseudoscalar I = e1^e2^e3^einf^eo (eq. 6).
template <class T>
[[nodiscard]] constexpr Pseudoscalar<T> pseudoscalar() noexcept {
  return Pseudoscalar<T>({T(1)});
}
/// Dual m* = -m I (eq. 7); dual(dual(m)) = -m.
template <class T, BladeMask M>
[[nodiscard]] constexpr auto dual(const Multivector<T, M>& m) noexcept {
  return -(m * pseudoscalar<T>());
}
/// Undual: the m with dual(m) = d, that is d I.
template <class T, BladeMask M>
[[nodiscard]] constexpr auto undual(const Multivector<T, M>& d) noexcept {
  return d * pseudoscalar<T>();
}

/// <a ~a>_0: the squared norm, which is indefinite in G(4,1) (negative for imaginary spheres).
template <class T, BladeMask M>
[[nodiscard]] constexpr T norm_squared(const Multivector<T, M>& a) noexcept {
  return scalar_product(a, reverse(a));
}
/// sqrt(|<a ~a>_0|).
template <class T, BladeMask M>
[[nodiscard]] T norm(const Multivector<T, M>& a) noexcept {
  return std::sqrt(std::abs(norm_squared(a)));
}

/// Largest absolute coefficient.
template <class T, BladeMask M>
[[nodiscard]] constexpr T max_abs(const Multivector<T, M>& a) noexcept {
  T m = 0;
  for (std::size_t i = 0; i < Multivector<T, M>::size; ++i) m = std::max(m, a[i] < 0 ? -a[i] : a[i]);
  return m;
}

/// True when every coefficient is finite.
template <class T, BladeMask M>
[[nodiscard]] bool is_finite(const Multivector<T, M>& a) noexcept {
  for (std::size_t i = 0; i < Multivector<T, M>::size; ++i)
    if (!std::isfinite(a[i])) return false;
  return true;
}

/// Inverse of a versor V (a product of invertible vectors, e.g. any Rotor, Translator,
/// Dilator, Motor or TRS Versor): ~V / <V ~V>_0.
/// @throws InvalidInputError when <V ~V>_0 is zero or not finite (V is not invertible).
template <class T, BladeMask M>
[[nodiscard]] Multivector<T, M> versor_inverse(const Multivector<T, M>& v) {
  const T n = norm_squared(v);
  if (n == T(0) || !std::isfinite(n))
    throw InvalidInputError("versor_inverse: the versor has zero or non-finite norm <V ~V> = " + std::to_string(n) +
                            " and cannot be inverted");
  return reverse(v) / n;
}

/// Inverse of any invertible multivector of G(4,1), in closed form (Hitzer & Sangwine 2017,
/// n = 5): with N = conj(a) inv(a) ~a and P = a N with grades 1 and 4 negated,
/// a^-1 = N P / <a N P>_0.
/// @throws InvalidInputError when a is not invertible (to working precision).
template <class T, BladeMask M>
[[nodiscard]] Dense<T> inverse(const Multivector<T, M>& a_in) {
  const Dense<T> a(a_in);
  const Dense<T> n = conjugate(a) * involution(a) * reverse(a);
  const Dense<T> p = detail::grade_signs<std::array<int, 6>{1, -1, 1, 1, -1, 1}>(Dense<T>(a * n));
  const Dense<T> np = n * p;
  const T den = scalar_product(a, np);
  // a N P is a degree-8 form in a's coefficients: compare against that scale.
  const T scale = std::pow(max_abs(a), T(8));
  if (!std::isfinite(den) || !(std::abs(den) > scale * std::numeric_limits<T>::epsilon() * T(64)))
    throw InvalidInputError("inverse: the multivector is not invertible (<a N P>_0 = " + std::to_string(den) + ")");
  return np / den;
}

}  // namespace cgamesh::cga
