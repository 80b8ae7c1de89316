// Products of G(4,1): the basis table against the metric (eq. 1-2, 6), and every sparse-type
// product against the same product of the widened dense operands.

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class BasisTable : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(BasisTable, FloatTypes);

/// Storage basis vector i (0..4 = e1, e2, e3, einf, eo).
template <class T>
Vector<T> null_vector(unsigned i) {
  Vector<T> v;
  v[i] = T(1);
  return v;
}

/// The five orthonormal vectors e1, e2, e3, e+, e- and their squares.
template <class T>
std::array<Vector<T>, 5> orthonormal_vectors() {
  return {euclidean<T>(1, 0, 0), euclidean<T>(0, 1, 0), euclidean<T>(0, 0, 1), e_plus<T>(), e_minus<T>()};
}
constexpr std::array<int, 5> kOrthonormalSquares{1, 1, 1, 1, -1};

TYPED_TEST(BasisTable, OrthonormalVectorsFollowTheMetric) {
  using T = TypeParam;
  const auto e = orthonormal_vectors<T>();
  for (unsigned i = 0; i < 5; ++i)
    for (unsigned j = 0; j < 5; ++j) {
      SCOPED_TRACE(::testing::Message() << "i=" << i << " j=" << j);
      const Dense<T> ij = e[i] * e[j];
      const Dense<T> ji = e[j] * e[i];
      if (i == j) {
        // e_i^2 = +-1: a pure scalar, all other blades exactly zero.
        EXPECT_MV_NEAR(ij, Scalar<T>({T(kOrthonormalSquares[i])}), T(0));
        EXPECT_EQ(scalar_product(e[i], e[i]), T(kOrthonormalSquares[i]));
      } else {
        // Orthogonal vectors anticommute, their product is their outer product (no scalar),
        // and (e_i e_j)^2 = -e_i^2 e_j^2.
        EXPECT_MV_NEAR(ij, -ji, T(0));
        EXPECT_EQ(scalar_part(ij), T(0));
        EXPECT_MV_NEAR(ij, e[i] ^ e[j], T(0));
        EXPECT_MV_NEAR(ij * ij, Scalar<T>({T(-kOrthonormalSquares[i] * kOrthonormalSquares[j])}), T(0));
        EXPECT_GT(max_abs(ij), T(0.5));
      }
    }
}

TYPED_TEST(BasisTable, NullVectorsFollowTheGramMatrix) {
  using T = TypeParam;
  // e_i . e_j of eq. (1): Euclidean orthonormal, einf^2 = eo^2 = 0, einf . eo = -1.
  constexpr std::array<std::array<int, 5>, 5> gram{{
      {1, 0, 0, 0, 0},
      {0, 1, 0, 0, 0},
      {0, 0, 1, 0, 0},
      {0, 0, 0, 0, -1},
      {0, 0, 0, -1, 0},
  }};
  for (unsigned i = 0; i < 5; ++i)
    for (unsigned j = 0; j < 5; ++j) {
      SCOPED_TRACE(::testing::Message() << "i=" << i << " j=" << j);
      const Vector<T> a = null_vector<T>(i), b = null_vector<T>(j);
      const Dense<T> ab = a * b, ba = b * a;
      // Symmetric part: the metric; antisymmetric part: the outer product.
      EXPECT_MV_NEAR(Dense<T>((ab + ba) * T(0.5)), Scalar<T>({T(gram[i][j])}), T(0));
      EXPECT_MV_NEAR(Dense<T>((ab - ba) * T(0.5)), a ^ b, T(0));
      EXPECT_EQ(scalar_product(a, b), T(gram[i][j]));
      // The stored blade of {i, j} is the outer product in increasing order.
      Dense<T> expected_outer;
      if (i != j) expected_outer[(1u << i) | (1u << j)] = T(i < j ? 1 : -1);
      EXPECT_MV_NEAR(a ^ b, expected_outer, T(0));
    }
}

TYPED_TEST(BasisTable, NamedIdentities) {
  using T = TypeParam;
  const Vector<T> o = eo<T>(), inf = einf<T>(), ep = e_plus<T>(), em = e_minus<T>();
  const Dense<T> zero;
  EXPECT_MV_NEAR(o * o, zero, T(0));      // eo^2 = 0
  EXPECT_MV_NEAR(inf * inf, zero, T(0));  // einf^2 = 0
  EXPECT_EQ(scalar_product(o, inf), T(-1));
  EXPECT_EQ(scalar_product(inf, o), T(-1));
  EXPECT_EQ(scalar_part(inf | o), T(-1));
  // einf eo = -1 + einf^eo, eo einf = -1 - einf^eo.
  const auto big_e = basis_blade<T, blade::info>();
  EXPECT_MV_NEAR(inf * o, T(-1) + big_e, T(0));
  EXPECT_MV_NEAR(o * inf, T(-1) + (-big_e), T(0));
  // einf ^ eo = e+ e- = e+ ^ e-, and (einf ^ eo)^2 = 1.
  EXPECT_MV_NEAR(inf ^ o, ep * em, T(0));
  EXPECT_MV_NEAR(inf ^ o, ep ^ em, T(0));
  EXPECT_MV_NEAR(big_e * big_e, Scalar<T>({T(1)}), T(0));
  EXPECT_MV_NEAR(o ^ inf, -(ep * em), T(0));
  // The basis change: einf = e+ + e-, eo = (e- - e+)/2.
  EXPECT_MV_NEAR(ep + em, inf, T(0));
  EXPECT_MV_NEAR((em - ep) * T(0.5), o, T(0));
  EXPECT_EQ(scalar_product(ep, em), T(0));
  EXPECT_MV_NEAR(ep * em, -(em * ep), T(0));
  // eo and einf are null but not zero, and the Euclidean vectors are orthogonal to both.
  for (unsigned i = 0; i < 3; ++i) {
    EXPECT_EQ(scalar_product(null_vector<T>(i), o), T(0));
    EXPECT_EQ(scalar_product(null_vector<T>(i), inf), T(0));
    EXPECT_MV_NEAR(null_vector<T>(i) * inf, -(inf * null_vector<T>(i)), T(0));
  }
}

std::string expected_blade_name(BladeIndex b) {
  if (b == 0) return "1";
  std::string s;
  if ((b & 7u) != 0) {
    s = "e";
    for (unsigned k = 0; k < 3; ++k)
      if ((b >> k) & 1u) s += static_cast<char>('1' + k);
  }
  if ((b & 8u) != 0) s += (s.empty() ? "" : "^") + std::string("einf");
  if ((b & 16u) != 0) s += (s.empty() ? "" : "^") + std::string("eo");
  return s;
}

TYPED_TEST(BasisTable, BladesAreOuterProductsInIncreasingOrder) {
  using T = TypeParam;
  for (BladeIndex b = 0; b < kBladeCount; ++b) {
    SCOPED_TRACE(::testing::Message() << "blade " << b);
    EXPECT_EQ(std::string(blade_name(b)), expected_blade_name(b));
    Dense<T> wedge(basis_blade<T, blade::scalar>());
    for (unsigned k = 0; k < 5; ++k)
      if ((b >> k) & 1u) wedge = wedge ^ Dense<T>(null_vector<T>(k));
    Dense<T> expected;
    expected[b] = T(1);
    EXPECT_MV_NEAR(wedge, expected, T(0));
    EXPECT_EQ(grade(b), static_cast<unsigned>(std::popcount(b)));
  }
  EXPECT_EQ(blade_name(blade::e13), "e13");
  EXPECT_EQ(blade_name(blade::info), "einf^eo");
  EXPECT_EQ(blade_name(blade::e2inf), "e2^einf");
  EXPECT_EQ(blade_name(blade::pseudoscalar), "e123^einf^eo");
}

TYPED_TEST(BasisTable, PseudoscalarIsBlade31) {
  using T = TypeParam;
  const auto i5 = euclidean<T>(1, 0, 0) ^ euclidean<T>(0, 1, 0) ^ euclidean<T>(0, 0, 1) ^ einf<T>() ^ eo<T>();
  static_assert(std::is_same_v<std::remove_const_t<decltype(i5)>, Pseudoscalar<T>>);
  EXPECT_EQ(i5.template get<blade::pseudoscalar>(), T(1));
  EXPECT_EQ(i5, pseudoscalar<T>());
  // I = e1 e2 e3 e+ e- (geometric product of the orthonormal vectors), and I^2 = -1.
  const auto e = orthonormal_vectors<T>();
  EXPECT_MV_NEAR(e[0] * e[1] * e[2] * e[3] * e[4], i5, T(0));
  EXPECT_MV_NEAR(i5 * i5, Scalar<T>({T(-1)}), T(0));
  // I commutes with every vector (odd dimension).
  for (unsigned k = 0; k < 5; ++k) EXPECT_MV_NEAR(i5 * null_vector<T>(k), null_vector<T>(k) * i5, T(0));
}

// ---------------------------------------------------------------- sparse == dense

template <class... Ts>
struct TypeList {};

template <class T>
using SparseTypes = TypeList<Scalar<T>, Vector<T>, Bivector<T>, Trivector<T>, Quadvector<T>, Pseudoscalar<T>,
                             Rotor<T>, Translator<T>, Dilator<T>, Motor<T>, Versor<T>>;

template <class A, class B>
void check_pair(Rng& rng, int cases) {
  using T = typename A::value_type;
  std::ostringstream name;
  name << std::hex << "mask 0x" << A::mask << " x mask 0x" << B::mask;
  SCOPED_TRACE(name.str());
  const T tol = pick<T>(1e-15, 1e-6);
  for (int k = 0; k < cases; ++k) {
    const A a = random_mv<A>(rng);
    const B b = random_mv<B>(rng);
    const Dense<T> da(a), db(b);
    // Each sparse product holds only blades its mask allows, and equals the dense product.
    EXPECT_MV_NEAR(a * b, da * db, tol);
    EXPECT_MV_NEAR(a ^ b, da ^ db, tol);
    EXPECT_MV_NEAR(a | b, da | db, tol);
    EXPECT_MV_NEAR(left_contraction(a, b), left_contraction(da, db), tol);
    EXPECT_MV_NEAR(right_contraction(a, b), right_contraction(da, db), tol);
    EXPECT_MV_NEAR(fat_dot(a, b), fat_dot(da, db), tol);
    EXPECT_NEAR(scalar_product(a, b), scalar_product(da, db), tol * 8);
    EXPECT_NEAR(scalar_product(a, b), scalar_part(da * db), tol * 8);
  }
}

template <class A, class... Bs>
void check_row(Rng& rng, int cases, TypeList<Bs...>) {
  (check_pair<A, Bs>(rng, cases), ...);
}
template <class... As>
void check_all_pairs(Rng& rng, int cases, TypeList<As...> list) {
  (check_row<As>(rng, cases, list), ...);
}

TEST(SparseProducts, AllPairsMatchDenseDouble) {
  Rng rng(0x5eed0001);
  check_all_pairs(rng, 5, SparseTypes<double>{});  // 121 pairs x 5 cases x 8 checks
}

TEST(SparseProducts, SomePairsMatchDenseFloat) {
  Rng rng(0x5eed0002);
  check_row<Motor<float>>(rng, 5, TypeList<Vector<float>, Motor<float>, Versor<float>, Trivector<float>>{});
  check_row<Versor<float>>(rng, 5, TypeList<Vector<float>, Bivector<float>, Versor<float>, Quadvector<float>>{});
  check_row<Translator<float>>(rng, 5, TypeList<Rotor<float>, Translator<float>, Dilator<float>>{});
}

TEST(SparseProducts, ProductDenseTimesDenseIsBilinear) {
  // The dense reference itself: bilinear in both arguments (catches a table that is not a
  // product, e.g. an accumulated instead of assigned coefficient).
  Rng rng(0x5eed0003);
  for (int k = 0; k < 200; ++k) {
    const auto a = random_mv<Dense<double>>(rng), b = random_mv<Dense<double>>(rng), c = random_mv<Dense<double>>(rng);
    const double s = rng.uniform(-2.0, 2.0);
    EXPECT_MV_NEAR((a + c * s) * b, a * b + (c * b) * s, 1e-14);
    EXPECT_MV_NEAR(a * (b + c * s), a * b + (a * c) * s, 1e-14);
    EXPECT_MV_NEAR((a + c * s) ^ b, (a ^ b) + (c ^ b) * s, 1e-14);
  }
}

template <class X, class Y>
constexpr bool same_mask = std::is_same_v<X, Y> && X::mask == Y::mask;

template <class T>
class ClosedTypes : public ::testing::Test {};
TYPED_TEST_SUITE(ClosedTypes, FloatTypes);

TYPED_TEST(ClosedTypes, VersorGroupsAreClosedAtCompileTime) {
  using T = TypeParam;
  static_assert(same_mask<decltype(Motor<T>() * Motor<T>()), Motor<T>>);
  static_assert(same_mask<decltype(Translator<T>() * Translator<T>()), Translator<T>>);
  static_assert(same_mask<decltype(Rotor<T>() * Rotor<T>()), Rotor<T>>);
  static_assert(same_mask<decltype(Versor<T>() * Versor<T>()), Versor<T>>);
  static_assert(same_mask<decltype(Dilator<T>() * Dilator<T>()), Dilator<T>>);
  static_assert(same_mask<decltype(Translator<T>() * Rotor<T>()), Motor<T>>);
  static_assert(same_mask<decltype(Vector<T>() ^ Vector<T>()), Bivector<T>>);
  static_assert(same_mask<decltype(Bivector<T>() ^ Vector<T>()), Trivector<T>>);
  static_assert(same_mask<decltype(Trivector<T>() ^ Vector<T>()), Quadvector<T>>);
  static_assert(same_mask<decltype(Vector<T>() | Vector<T>()), Scalar<T>>);
  EXPECT_EQ(decltype(Motor<T>() * Motor<T>())::mask, mask::motor);
  EXPECT_EQ(decltype(Versor<T>() * Versor<T>())::mask, mask::versor);
  EXPECT_EQ(decltype(Translator<T>() * Translator<T>())::mask, mask::translator);
  EXPECT_EQ(decltype(Rotor<T>() * Rotor<T>())::mask, mask::rotor);
  // The mask of the geometric product is exactly what can be non-zero: the dense product of
  // random motors has the e123^einf blade, the translator product never the rotor blades.
  Rng rng(17);
  const Motor<T> m1 = random_mv<Motor<T>>(rng), m2 = random_mv<Motor<T>>(rng);
  EXPECT_NE((m1 * m2).template get<blade::e123inf>(), T(0));
  const Dense<T> tt = Dense<T>(random_mv<Translator<T>>(rng)) * Dense<T>(random_mv<Translator<T>>(rng));
  for (BladeIndex b = 0; b < kBladeCount; ++b)
    if (!has_blade(mask::translator, b)) {
      EXPECT_EQ(tt[b], T(0)) << blade_name(b);
    }
}

TEST(Products, ProductPartComputesOnlyTheRequestedBlades) {
  Rng rng(23);
  for (int k = 0; k < 100; ++k) {
    const auto v = random_mv<Versor<double>>(rng);
    const auto x = random_mv<Vector<double>>(rng);
    const auto part = product_part<mask::vector>(v * x, reverse(v));
    static_assert(decltype(part)::mask == mask::vector);
    EXPECT_MV_NEAR(part, grade_part<1>(Dense<double>(v * x * reverse(v))), 1e-14);
  }
}

}  // namespace
