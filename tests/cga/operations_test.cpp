// Unary operations and algebraic laws on random dense multivectors: associativity,
// anti-automorphisms, duality (eq. 7) and inverses.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cmath>
#include <limits>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class DenseLaws : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(DenseLaws, FloatTypes);

/// Random cases per law: 1000 in double (3000 multivectors for associativity), fewer in float.
template <class T>
constexpr int kCases = sizeof(T) >= sizeof(double) ? 1000 : 300;

TYPED_TEST(DenseLaws, ProductsAreAssociative) {
  using T = TypeParam;
  Rng rng(0xa55 + sizeof(T));
  const T tol = pick<T>(1e-14, 2e-5);
  for (int k = 0; k < kCases<T>; ++k) {
    const auto a = random_mv<Dense<T>>(rng), b = random_mv<Dense<T>>(rng), c = random_mv<Dense<T>>(rng);
    ASSERT_MV_NEAR((a * b) * c, a * (b * c), tol) << "case " << k;
    ASSERT_MV_NEAR((a ^ b) ^ c, a ^ (b ^ c), tol) << "case " << k;
  }
}

TYPED_TEST(DenseLaws, InvolutionsActOnProducts) {
  using T = TypeParam;
  Rng rng(0xb66 + sizeof(T));
  const T tol = pick<T>(1e-14, 2e-6);
  for (int k = 0; k < kCases<T>; ++k) {
    const auto a = random_mv<Dense<T>>(rng), b = random_mv<Dense<T>>(rng);
    const Dense<T> ab = a * b;
    ASSERT_MV_NEAR(reverse(ab), reverse(b) * reverse(a), tol) << "case " << k;
    ASSERT_MV_NEAR(involution(ab), involution(a) * involution(b), tol) << "case " << k;
    ASSERT_MV_NEAR(conjugate(ab), conjugate(b) * conjugate(a), tol) << "case " << k;
    // Outer product: reverse is an anti-automorphism of ^ as well.
    ASSERT_MV_NEAR(reverse(Dense<T>(a ^ b)), reverse(b) ^ reverse(a), tol) << "case " << k;
  }
}

TYPED_TEST(DenseLaws, InvolutionSignsPerGrade) {
  using T = TypeParam;
  constexpr std::array<int, 6> rev{1, 1, -1, -1, 1, 1}, inv{1, -1, 1, -1, 1, -1}, conj{1, -1, -1, 1, 1, -1};
  for (BladeIndex b = 0; b < kBladeCount; ++b) {
    Dense<T> x;
    x[b] = T(3);
    EXPECT_EQ(reverse(x)[b], T(3 * rev[grade(b)])) << blade_name(b);
    EXPECT_EQ(involution(x)[b], T(3 * inv[grade(b)])) << blade_name(b);
    EXPECT_EQ(conjugate(x)[b], T(3 * conj[grade(b)])) << blade_name(b);
    EXPECT_EQ(max_abs(reverse(x)), T(3));
  }
}

TYPED_TEST(DenseLaws, DualAndUndual) {
  using T = TypeParam;
  Rng rng(0xc77 + sizeof(T));
  const T tol = pick<T>(1e-15, 1e-6);
  for (int k = 0; k < kCases<T>; ++k) {
    const auto m = random_mv<Dense<T>>(rng);
    const Dense<T> d = dual(m);
    ASSERT_MV_NEAR(dual(d), -m, tol) << "case " << k;  // (m*)* = -m
    ASSERT_MV_NEAR(undual(d), m, tol) << "case " << k;
    ASSERT_MV_NEAR(dual(undual(m)), m, tol) << "case " << k;
    ASSERT_MV_NEAR(d, -(m * pseudoscalar<T>()), T(0)) << "case " << k;  // eq. (7)
  }
  // Duality maps grade g to grade 5 - g: e.g. the dual of a vector is a 4-vector.
  const Vector<T> v = random_mv<Vector<T>>(rng);
  const auto dv = dual(v);
  EXPECT_EQ(decltype(dv)::mask, mask::quadvector);
  EXPECT_MV_NEAR(dv, grade_part<4>(Dense<T>(dv)), T(0));
  EXPECT_GT(max_abs(dv), T(0));
  // dual(e1) = -e1 I = -e23^einf^eo.
  Dense<T> expected;
  expected[blade::e23 | blade::info] = T(-1);
  EXPECT_MV_NEAR(dual(euclidean<T>(1, 0, 0)), expected, T(0));
}

TYPED_TEST(DenseLaws, GradePartsAndNorms) {
  using T = TypeParam;
  Rng rng(0xd88 + sizeof(T));
  const auto m = random_mv<Dense<T>>(rng);
  const Dense<T> sum = Dense<T>(grade_part<0>(m)) + grade_part<1>(m) + grade_part<2>(m) + grade_part<3>(m) +
                       grade_part<4>(m) + grade_part<5>(m);
  EXPECT_MV_NEAR(sum, m, T(0));
  EXPECT_EQ(decltype(grade_part<3>(m))::size, 10u);
  EXPECT_EQ(scalar_part(m), m[0]);
  // Norms of the basis: e1 has norm 1, eo is null, e- has <e- ~e-> = -1, a sphere of radius r
  // has S^2 = r^2.
  EXPECT_EQ(norm_squared(euclidean<T>(1, 0, 0)), T(1));
  EXPECT_EQ(norm_squared(eo<T>()), T(0));
  EXPECT_EQ(norm_squared(e_minus<T>()), T(-1));
  EXPECT_EQ(norm(e_minus<T>()), T(1));
  EXPECT_NEAR(norm_squared(sphere<T>(Vec3<T>(1, 2, 3), T(2))), T(4), pick<T>(1e-14, 1e-5));
  EXPECT_EQ(max_abs(make_vector<T>(1, -7, 3, 0, 2)), T(7));
  EXPECT_TRUE(is_finite(m));
  Dense<T> bad = m;
  bad[17] = std::numeric_limits<T>::quiet_NaN();
  EXPECT_FALSE(is_finite(bad));
  bad[17] = std::numeric_limits<T>::infinity();
  EXPECT_FALSE(is_finite(bad));
}

TEST(Inverse, RandomDenseDouble) {
  Rng rng(0xe99);
  double worst = 0;
  for (int k = 0; k < kCases<double>; ++k) {
    const auto m = random_mv<Dense<double>>(rng);
    const Dense<double> inv = inverse(m);
    // Residual relative to the conditioning |m| |m^-1| of the product.
    const double cond = std::max(1.0, max_abs(m) * max_abs(inv));
    const Dense<double> one(basis_blade<double, blade::scalar>());
    ASSERT_MV_NEAR(m * inv, one, 1e-12 * cond) << "case " << k;
    ASSERT_MV_NEAR(inv * m, one, 1e-12 * cond) << "case " << k;
    worst = std::max(worst, max_abs(Dense<double>(m * inv - one)) / cond);
  }
  EXPECT_GT(worst, 0.0);  // not exact: the check above is not vacuous
}

TEST(Inverse, WellConditionedFloat) {
  // In float the degree-8 closed form loses ~cond^2 eps: test on well-conditioned inputs
  // (dominant scalar part), and compare with the double-precision inverse.
  Rng rng(0xe9a);
  for (int k = 0; k < 100; ++k) {
    const auto md = Dense<double>(3.0 + random_mv<Dense<double>>(rng, -0.3, 0.3));
    Dense<float> mf;
    for (std::size_t i = 0; i < kBladeCount; ++i) mf[i] = static_cast<float>(md[i]);
    const Dense<float> inv = inverse(mf);
    const Dense<float> one(basis_blade<float, blade::scalar>());
    ASSERT_MV_NEAR(mf * inv, one, 2e-6f) << "case " << k;
    ASSERT_MV_NEAR(inv * mf, one, 2e-6f) << "case " << k;
    const Dense<double> invd = inverse(md);
    for (std::size_t i = 0; i < kBladeCount; ++i) ASSERT_NEAR(inv[i], invd[i], 1e-6) << "case " << k << " blade " << i;
  }
}

TEST(Inverse, SparseTypesAndKnownValues) {
  // (2 e1)^-1 = e1 / 2; e+^-1 = e+, e-^-1 = -e-; I^-1 = -I; a dilator's inverse is its reverse.
  EXPECT_MV_NEAR(inverse(euclidean<double>(2, 0, 0)), euclidean<double>(0.5, 0, 0), 1e-15);
  EXPECT_MV_NEAR(inverse(e_plus<double>()), e_plus<double>(), 1e-15);
  EXPECT_MV_NEAR(inverse(e_minus<double>()), -e_minus<double>(), 1e-15);
  EXPECT_MV_NEAR(inverse(pseudoscalar<double>()), -pseudoscalar<double>(), 1e-15);
  EXPECT_MV_NEAR(inverse(dilator(3.0)), reverse(dilator(3.0)), 1e-15);
  // A sphere (non-null vector) is invertible: S^-1 = S / S^2.
  const Vector<double> s = sphere<double>(Vec3<double>(1, -2, 0.5), 1.5);
  EXPECT_MV_NEAR(inverse(s), s / scalar_product(s, s), 1e-14);
}

TEST(Inverse, NonInvertibleThrows) {
  // Null vectors: eo, einf and every point.
  EXPECT_THROW((void)inverse(eo<double>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)inverse(einf<double>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)inverse(up(Vec3<double>(1, 2, 3))), cgamesh::InvalidInputError);
  // 1 + E with E = einf^eo, E^2 = 1: (1 + E)(1 - E) = 0, a zero divisor.
  const auto big_e = basis_blade<double, blade::info>();
  const auto zero_divisor = 1.0 + big_e;
  EXPECT_MV_NEAR(zero_divisor * (1.0 + (-big_e)), Dense<double>(), 0.0);
  EXPECT_THROW((void)inverse(zero_divisor), cgamesh::InvalidInputError);
  EXPECT_THROW((void)inverse(1.0f + basis_blade<float, blade::info>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)inverse(Dense<double>()), cgamesh::InvalidInputError);
  Dense<double> nan_mv(basis_blade<double, blade::scalar>());
  nan_mv[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)inverse(nan_mv), cgamesh::InvalidInputError);
  // versor_inverse needs <V ~V> != 0.
  EXPECT_THROW((void)versor_inverse(eo<double>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)versor_inverse(Versor<double>()), cgamesh::InvalidInputError);
  // But 1 + 0.5 E is invertible: (1 - 0.5 E) / 0.75.
  const auto invertible = 1.0 + big_e * 0.5;
  EXPECT_MV_NEAR(inverse(invertible), (1.0 + big_e * -0.5) / 0.75, 1e-15);
}

TEST(Inverse, VersorInverseAgreesWithInverse) {
  Rng rng(0xf00);
  for (int k = 0; k < 150; ++k) {
    // Even TRS versors, with a random non-unit scale factor.
    const Similarity<double> sim = random_similarity<double>(rng);
    const Versor<double> v = sim.versor() * rng.uniform(0.5, 2.0);
    const Dense<double> vi = versor_inverse(v);
    ASSERT_MV_NEAR(vi, inverse(v), 1e-12) << "case " << k;
    ASSERT_MV_NEAR(v * vi, Scalar<double>({1.0}), 1e-12) << "case " << k;
    // Odd versors: products of three random non-null vectors.
    Vector<double> x[3];
    for (auto& xi : x) {
      do xi = random_mv<Vector<double>>(rng);
      while (std::abs(scalar_product(xi, xi)) < 0.1);
    }
    const auto odd = x[0] * x[1] * x[2];
    const auto odd_versor = project<mask::vector | mask::trivector | mask::pseudoscalar>(odd);
    ASSERT_MV_NEAR(odd_versor, odd, 0.0);
    ASSERT_MV_NEAR(versor_inverse(odd_versor), inverse(odd_versor), 1e-11) << "case " << k;
    // Sparse versors of every named type.
    const Motor<double> m = sim.motor();
    ASSERT_MV_NEAR(versor_inverse(m), inverse(m), 1e-12);
    ASSERT_MV_NEAR(versor_inverse(sim.rotor()), reverse(sim.rotor()), 1e-15);
  }
}

}  // namespace
