#pragma once
// Products of G(4,1) (paper section 2.2). Each product of two types is expanded at compile
// time into the list of its non-zero blade terms, and that list into straight-line code: no
// run-time loop over a 32x32 table, whatever the types.

#include <array>
#include <cstddef>
#include <utility>

#include "cgamesh/cga/blade.hpp"
#include "cgamesh/cga/multivector.hpp"

namespace cgamesh::cga {

/// Which bilinear product: each keeps a subset of the geometric product's blade terms.
enum class ProductKind {
  geometric,          ///< a b
  outer,              ///< a ^ b: grade ga + gb
  left_contraction,   ///< a _| b: grade gb - ga, zero when ga > gb
  right_contraction,  ///< a |_ b: grade ga - gb, zero when gb > ga
  inner,              ///< Hestenes inner product: grade |ga - gb|, zero when a or b is a scalar
  fat_dot,            ///< grade |ga - gb|, scalars included (Dorst's "fat dot")
  scalar              ///< <a b>_0
};

namespace detail {

/// Whether product K keeps the grade-gr part of the product of grades ga and gb.
[[nodiscard]] constexpr bool keeps(ProductKind kind, unsigned ga, unsigned gb, unsigned gr) noexcept {
  const int d = static_cast<int>(gb) - static_cast<int>(ga);
  switch (kind) {
    case ProductKind::geometric: return true;
    case ProductKind::outer: return gr == ga + gb;
    case ProductKind::left_contraction: return d >= 0 && static_cast<int>(gr) == d;
    case ProductKind::right_contraction: return d <= 0 && static_cast<int>(gr) == -d;
    case ProductKind::inner: return ga != 0 && gb != 0 && static_cast<int>(gr) == (d < 0 ? -d : d);
    case ProductKind::fat_dot: return static_cast<int>(gr) == (d < 0 ? -d : d);
    case ProductKind::scalar: return gr == 0;
  }
  return false;
}

struct Term {
  unsigned a;  ///< storage index in the left operand
  unsigned b;  ///< storage index in the right operand
  unsigned r;  ///< storage index in the result
  double coef;
};

template <ProductKind K, BladeMask A, BladeMask B, BladeMask Keep, class F>
constexpr void for_each_term(F&& f) {
  for (BladeIndex a = 0; a < kBladeCount; ++a) {
    if (!has_blade(A, a)) continue;
    for (BladeIndex b = 0; b < kBladeCount; ++b) {
      if (!has_blade(B, b)) continue;
      const auto& s = kBladeProducts[a][b];
      for (unsigned i = 0; i < s.n; ++i)
        if (has_blade(Keep, s.blade[i]) && keeps(K, grade(a), grade(b), grade(s.blade[i])))
          f(a, b, s.blade[i], s.coef[i]);
    }
  }
}

/// The terms of product K of types A and B that land on blades in Keep.
template <ProductKind K, BladeMask A, BladeMask B, BladeMask Keep = kAllBlades>
struct ProductTable {
  static constexpr BladeMask result_mask = [] {
    BladeMask m = 0;
    for_each_term<K, A, B, Keep>([&](BladeIndex, BladeIndex, BladeIndex r, double) { m |= BladeMask{1} << r; });
    return m;
  }();
  static constexpr std::size_t count = [] {
    std::size_t n = 0;
    for_each_term<K, A, B, Keep>([&](BladeIndex, BladeIndex, BladeIndex, double) { ++n; });
    return n;
  }();
  static constexpr std::array<Term, count> terms = [] {
    std::array<Term, count> out{};
    std::size_t n = 0;
    for_each_term<K, A, B, Keep>([&](BladeIndex a, BladeIndex b, BladeIndex r, double c) {
      out[n++] = Term{storage_index(A, a), storage_index(B, b), storage_index(result_mask, r), c};
    });
    return out;
  }();
};

template <ProductKind K, BladeMask Keep, class T, BladeMask A, BladeMask B, std::size_t... I>
[[nodiscard]] constexpr auto expand(const Multivector<T, A>& a, const Multivector<T, B>& b,
                                    std::index_sequence<I...>) noexcept {
  using Table = ProductTable<K, A, B, Keep>;
  Multivector<T, Table::result_mask> out;
  // Coefficients are +-1 or +-1/2 (exact), so multiplying by them costs nothing after folding.
  ((out[Table::terms[I].r] += T(Table::terms[I].coef) * (a[Table::terms[I].a] * b[Table::terms[I].b])), ...);
  return out;
}

}  // namespace detail

/// Any of the products of ProductKind; the result holds exactly the blades that can be non-zero.
template <ProductKind K, class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto product(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return detail::expand<K, kAllBlades>(a, b, std::make_index_sequence<detail::ProductTable<K, A, B>::count>{});
}

/// The part of product K on the blades in Keep, computing nothing else (e.g. the grade-1 part
/// of a sandwich).
template <BladeMask Keep, ProductKind K = ProductKind::geometric, class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto product_part(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return detail::expand<K, Keep>(a, b, std::make_index_sequence<detail::ProductTable<K, A, B, Keep>::count>{});
}

/// Geometric product a b.
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto operator*(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::geometric>(a, b);
}
/// Outer product a ^ b.
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto operator^(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::outer>(a, b);
}
/// The paper's inner product a . b (Hestenes: grade |ga - gb|, zero with a scalar factor).
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto operator|(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::inner>(a, b);
}
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto outer(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::outer>(a, b);
}
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto inner(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::inner>(a, b);
}
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto left_contraction(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::left_contraction>(a, b);
}
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto right_contraction(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::right_contraction>(a, b);
}
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto fat_dot(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::fat_dot>(a, b);
}
/// Scalar product <a b>_0, as a plain number.
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr T scalar_product(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return product<ProductKind::scalar>(a, b).template get<blade::scalar>();
}

// The null basis of eq. (1): eo^2 = einf^2 = 0 and eo . einf = -1.
static_assert(scalar_product(eo<double>(), eo<double>()) == 0.0);
static_assert(scalar_product(einf<double>(), einf<double>()) == 0.0);
static_assert(scalar_product(eo<double>(), einf<double>()) == -1.0);
static_assert((einf<double>() ^ eo<double>()).get<blade::info>() == 1.0);
static_assert((e_plus<double>() * e_minus<double>()).get<blade::info>() == 1.0);  // e+ e- = einf ^ eo
static_assert(scalar_product(e_minus<double>(), e_minus<double>()) == -1.0);
// Closure of the versor types: rotor * translator is a motor; motors and versors are groups.
static_assert(detail::ProductTable<ProductKind::geometric, mask::translator, mask::rotor>::result_mask == mask::motor);
static_assert(detail::ProductTable<ProductKind::geometric, mask::motor, mask::motor>::result_mask == mask::motor);
static_assert(detail::ProductTable<ProductKind::geometric, mask::versor, mask::versor>::result_mask == mask::versor);

}  // namespace cgamesh::cga
