#pragma once
// Blade order and basis products of G(4,1): stated once here, checked by static_assert.
//
// Storage basis is the paper's null basis (eq. 1-2): e1, e2, e3, einf, eo with
//     e_i . e_j = delta_ij,  einf . einf = eo . eo = 0,  einf . eo = -1,
// so that points, translators and motors need no more coefficients than they have degrees
// of freedom, and motor * motor is a motor at compile time. A blade is named by a bitmask:
//     bit 0 = e1, bit 1 = e2, bit 2 = e3, bit 3 = einf, bit 4 = eo
// and stands for the OUTER product of its vectors in increasing bit order (blade 0b00101 =
// e1^e3, blade 0b11000 = einf^eo, blade 31 = e1^e2^e3^einf^eo = I of eq. 6). Coefficients are
// stored in increasing blade index. The orthonormal e+ and e- of the paper are derived:
//     e+ = einf/2 - eo,  e- = einf/2 + eo,  e+ e- = einf ^ eo.

#include <array>
#include <bit>
#include <cstdint>
#include <string_view>

namespace cgamesh::cga {

/// Index of a blade: a bitmask over (e1, e2, e3, einf, eo).
using BladeIndex = unsigned;
/// A set of blades: bit i set when blade i is present.
using BladeMask = std::uint32_t;

inline constexpr unsigned kDimension = 5;
inline constexpr unsigned kBladeCount = 1u << kDimension;

/// Named blades of the storage basis.
namespace blade {
inline constexpr BladeIndex scalar = 0;
inline constexpr BladeIndex e1 = 1;
inline constexpr BladeIndex e2 = 2;
inline constexpr BladeIndex e3 = 4;
inline constexpr BladeIndex einf = 8;
inline constexpr BladeIndex eo = 16;
inline constexpr BladeIndex e12 = e1 | e2;
inline constexpr BladeIndex e13 = e1 | e3;
inline constexpr BladeIndex e23 = e2 | e3;
inline constexpr BladeIndex e123 = e1 | e2 | e3;
inline constexpr BladeIndex e1inf = e1 | einf;
inline constexpr BladeIndex e2inf = e2 | einf;
inline constexpr BladeIndex e3inf = e3 | einf;
inline constexpr BladeIndex e123inf = e123 | einf;
inline constexpr BladeIndex info = einf | eo;  ///< einf ^ eo = e+ e-
inline constexpr BladeIndex pseudoscalar = 31;  ///< I = e1^e2^e3^einf^eo (eq. 6)
}  // namespace blade

/// Inner products of the basis vectors (the metric of eq. 1 in the null basis).
inline constexpr std::array<std::array<int, kDimension>, kDimension> kGram{{
    {1, 0, 0, 0, 0},
    {0, 1, 0, 0, 0},
    {0, 0, 1, 0, 0},
    {0, 0, 0, 0, -1},
    {0, 0, 0, -1, 0},
}};

[[nodiscard]] constexpr unsigned grade(BladeIndex b) noexcept { return static_cast<unsigned>(std::popcount(b)); }

/// Sign from reordering the vectors of blade a followed by blade b into increasing order.
[[nodiscard]] constexpr int reorder_sign(BladeIndex a, BladeIndex b) noexcept {
  unsigned swaps = 0;
  for (BladeIndex x = a >> 1; x != 0; x >>= 1) swaps += grade(x & b);
  return (swaps & 1u) != 0 ? -1 : 1;
}

/// Mask of all blades of grade g.
[[nodiscard]] constexpr std::uint32_t grade_mask(unsigned g) noexcept {
  std::uint32_t m = 0;
  for (BladeIndex b = 0; b < kBladeCount; ++b)
    if (grade(b) == g) m |= std::uint32_t{1} << b;
  return m;
}

[[nodiscard]] constexpr bool has_blade(BladeMask m, BladeIndex b) noexcept { return ((m >> b) & 1u) != 0; }

/// Position of blade b inside the coefficient array of a type with mask m.
[[nodiscard]] constexpr unsigned storage_index(BladeMask m, BladeIndex b) noexcept {
  return static_cast<unsigned>(std::popcount(m & ((BladeMask{1} << b) - 1u)));
}

/// Name of a blade ("1", "e1", "e13", "e1^einf", "einf^eo").
[[nodiscard]] constexpr std::string_view blade_name(BladeIndex b) noexcept {
  constexpr std::array<std::string_view, kBladeCount> names{
      "1",          "e1",          "e2",          "e12",          "e3",          "e13",          "e23",          "e123",
      "einf",       "e1^einf",     "e2^einf",     "e12^einf",     "e3^einf",     "e13^einf",     "e23^einf",     "e123^einf",
      "eo",         "e1^eo",       "e2^eo",       "e12^eo",       "e3^eo",       "e13^eo",       "e23^eo",       "e123^eo",
      "einf^eo",    "e1^einf^eo",  "e2^einf^eo",  "e12^einf^eo",  "e3^einf^eo",  "e13^einf^eo",  "e23^einf^eo",  "e123^einf^eo"};
  return names[b];
}

inline constexpr BladeMask kAllBlades = 0xFFFFFFFFu;
inline constexpr BladeMask kEvenBlades = grade_mask(0) | grade_mask(2) | grade_mask(4);

namespace detail {

/// A multivector with at most four blades that differ only in their einf/eo bits: what one
/// basis blade becomes in the other basis, and what a product of two basis blades gives.
struct SmallSum {
  unsigned n = 0;
  std::array<BladeIndex, 4> blade{};
  std::array<double, 4> coef{};
  constexpr void add(BladeIndex b, double c) {
    for (unsigned i = 0; i < n; ++i)
      if (blade[i] == b) {
        coef[i] += c;
        return;
      }
    blade[n] = b;
    coef[n++] = c;
  }
};

// Orthonormal helper basis (same bit layout, bit 3 = e+, bit 4 = e-), used only to derive the
// product table: there every basis product is a signed blade.
inline constexpr std::array<int, kDimension> kOrthonormalSquares{1, 1, 1, 1, -1};

[[nodiscard]] constexpr SmallSum null_to_orthonormal(BladeIndex b) {
  // b = E ^ X with E Euclidean (orthogonal to X): einf = e+ + e-, eo = (e- - e+)/2,
  // einf ^ eo = e+ e-.
  const BladeIndex e = b & 7u;
  SmallSum s;
  switch (b >> 3) {
    case 0: s.add(e, 1); break;
    case 1: s.add(e | 8u, 1); s.add(e | 16u, 1); break;
    case 2: s.add(e | 8u, -0.5); s.add(e | 16u, 0.5); break;
    default: s.add(e | 24u, 1); break;
  }
  return s;
}

[[nodiscard]] constexpr SmallSum orthonormal_to_null(BladeIndex b) {
  // e+ = einf/2 - eo, e- = einf/2 + eo, e+ e- = einf ^ eo.
  const BladeIndex e = b & 7u;
  SmallSum s;
  switch (b >> 3) {
    case 0: s.add(e, 1); break;
    case 1: s.add(e | 8u, 0.5); s.add(e | 16u, -1); break;
    case 2: s.add(e | 8u, 0.5); s.add(e | 16u, 1); break;
    default: s.add(e | 24u, 1); break;
  }
  return s;
}

[[nodiscard]] constexpr int orthonormal_gp_sign(BladeIndex a, BladeIndex b) {
  int sign = reorder_sign(a, b);
  for (unsigned i = 0; i < kDimension; ++i)
    if (((a & b) >> i) & 1u) sign *= kOrthonormalSquares[i];
  return sign;
}

[[nodiscard]] constexpr SmallSum blade_product(BladeIndex a, BladeIndex b) {
  const SmallSum oa = null_to_orthonormal(a);
  const SmallSum ob = null_to_orthonormal(b);
  SmallSum out;
  for (unsigned i = 0; i < oa.n; ++i)
    for (unsigned j = 0; j < ob.n; ++j) {
      const double c = oa.coef[i] * ob.coef[j] * orthonormal_gp_sign(oa.blade[i], ob.blade[j]);
      const SmallSum back = orthonormal_to_null(oa.blade[i] ^ ob.blade[j]);
      for (unsigned k = 0; k < back.n; ++k) out.add(back.blade[k], c * back.coef[k]);
    }
  SmallSum nonzero;
  for (unsigned k = 0; k < out.n; ++k)
    if (out.coef[k] != 0) nonzero.add(out.blade[k], out.coef[k]);
  return nonzero;
}

}  // namespace detail

/// Geometric product of every pair of basis blades: kBladeProducts[a][b] lists (blade, coef).
inline constexpr auto kBladeProducts = [] {
  std::array<std::array<detail::SmallSum, kBladeCount>, kBladeCount> t{};
  for (BladeIndex a = 0; a < kBladeCount; ++a)
    for (BladeIndex b = 0; b < kBladeCount; ++b) t[a][b] = detail::blade_product(a, b);
  return t;
}();

/// Coefficient of blade r in the geometric product of basis blades a and b.
[[nodiscard]] constexpr double blade_product_coefficient(BladeIndex a, BladeIndex b, BladeIndex r) noexcept {
  const auto& s = kBladeProducts[a][b];
  for (unsigned i = 0; i < s.n; ++i)
    if (s.blade[i] == r) return s.coef[i];
  return 0;
}

// The order and the metric are load-bearing for every stored coefficient: check them.
static_assert(kBladeCount == 32);
static_assert(blade::e13 == 5 && blade::info == 24 && blade::pseudoscalar == 31);
static_assert(blade_name(blade::e13) == "e13" && blade_name(blade::info) == "einf^eo");
static_assert(grade_mask(1) == 0b00000000000000010000000100010110u);
static_assert(std::popcount(kEvenBlades) == 16);
// The products of the basis vectors reproduce the Gram matrix: e_i e_j = e_i . e_j + e_i ^ e_j.
static_assert([] {
  for (unsigned i = 0; i < kDimension; ++i)
    for (unsigned j = 0; j < kDimension; ++j) {
      const BladeIndex a = 1u << i, b = 1u << j;
      if (blade_product_coefficient(a, b, 0) != kGram[i][j]) return false;
      if (i != j && blade_product_coefficient(a, b, a | b) != (i < j ? 1 : -1)) return false;
    }
  return true;
}());
static_assert(blade_product_coefficient(blade::einf, blade::eo, blade::scalar) == -1);  // eo . einf = -1
static_assert(blade_product_coefficient(blade::eo, blade::eo, blade::scalar) == 0);      // eo^2 = 0
static_assert(kBladeProducts[blade::einf][blade::einf].n == 0);                          // einf^2 = 0
static_assert(blade_product_coefficient(blade::info, blade::info, blade::scalar) == 1);  // (einf^eo)^2 = 1
static_assert(blade_product_coefficient(blade::pseudoscalar, blade::pseudoscalar, 0) == -1);  // I^2 = -1

}  // namespace cgamesh::cga
