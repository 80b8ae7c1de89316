// Interpolation of versors (paper section 2.5): lerp, normalisation, log blend and n-way blend.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class Interpolation : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Interpolation, FloatTypes);

TYPED_TEST(Interpolation, LerpEndpointsAndMidpoint) {
  using T = TypeParam;
  Rng rng(0x60001 + sizeof(T));
  for (int k = 0; k < 200; ++k) {
    const auto a = random_mv<Versor<T>>(rng), b = random_mv<Versor<T>>(rng);
    EXPECT_MV_NEAR(lerp(a, b, T(0)), a, T(0));
    EXPECT_MV_NEAR(lerp(a, b, T(1)), b, T(0));
    EXPECT_MV_NEAR(lerp(a, b, T(0.25)), Versor<T>(a * T(0.75) + b * T(0.25)), pick<T>(1e-15, 1e-7));
  }
}

/// V ~V = 1 exactly in every blade (in particular no grade-4 part).
template <class T, BladeMask M>
::testing::AssertionResult is_unit(const Multivector<T, M>& v, T tol) {
  return mv_near(v * reverse(v), Scalar<T>({T(1)}), tol);
}

TYPED_TEST(Interpolation, LerpNormalizedGivesUnitVersors) {
  using T = TypeParam;
  const T tol = pick<T>(1e-13, 1e-5);
  Rng rng(0x60002 + sizeof(T));
  for (int k = 0; k < 1000; ++k) {
    const auto f1 = random_similarity<T>(rng), f2 = random_similarity<T>(rng);
    const T alpha = rng.uniform<T>(0, 1);
    // Lerp between versors in the same hemisphere (<V1 ~V2> >= 0), so that <V ~V> > 0.
    const auto hemi = [](const auto& v1, const auto& v2) { return scalar_product(v1, reverse(v2)) < 0 ? -v2 : v2; };
    // Motors: the plain lerp has a grade-4 (e123^einf) part in M ~M; normalising removes it.
    const Motor<T> m1 = f1.motor(), m2 = hemi(m1, f2.motor());
    const Motor<T> lm = lerp(m1, m2, alpha);
    const Motor<T> nm = lerp_normalized(m1, m2, alpha);
    ASSERT_TRUE(is_unit(nm, tol)) << "motor, case " << k;
    EXPECT_NEAR((nm * reverse(nm)).template get<blade::e123inf>(), T(0), tol);
    if (k == 0) {
      EXPECT_GT(std::abs((lm * reverse(lm)).template get<blade::e123inf>()), T(1e-3));
    }
    // The normalised motor is a positive multiple of the lerp up to its grade-4 correction: the
    // rotor parts are parallel.
    const Rotor<T> rl = project<mask::rotor>(lm), rn = project<mask::rotor>(nm);
    EXPECT_MV_NEAR(Rotor<T>(rn * (norm(rl) / norm(rn))), rl, tol * T(10));
    // Rotors and TRS versors.
    const Rotor<T> nr = lerp_normalized(f1.rotor(), hemi(f1.rotor(), f2.rotor()), alpha);
    ASSERT_TRUE(is_unit(nr, tol)) << "rotor, case " << k;
    const Versor<T> nv = lerp_normalized(f1.versor(), hemi(f1.versor(), f2.versor()), alpha);
    ASSERT_TRUE(is_unit(nv, tol * T(10))) << "versor, case " << k;
  }
  // Normalising a multiple of a unit versor gives the versor back.
  const auto f = random_similarity<T>(rng);
  EXPECT_MV_NEAR(normalized(Versor<T>(f.versor() * T(3))), f.versor(), tol);
  EXPECT_MV_NEAR(normalized(Motor<T>(f.motor() * T(0.2))), f.motor(), tol);
  EXPECT_THROW((void)normalized(Versor<T>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)normalized(Versor<T>(basis_blade<T, blade::e1 | blade::e2>() * basis_blade<T, blade::e3 | blade::eo>())),
               cgamesh::InvalidInputError);
}

TYPED_TEST(Interpolation, LogBlendEndpointsAndSymmetry) {
  using T = TypeParam;
  const T tol = pick<T>(1e-11, 2e-4);
  Rng rng(0x60003 + sizeof(T));
  for (int k = 0; k < 400; ++k) {
    const auto f1 = random_similarity<T>(rng), f2 = random_similarity<T>(rng);
    const T t = rng.uniform<T>(0, 1);
    // Rotors.
    const Rotor<T> r1 = f1.rotor(), r2 = f2.rotor();
    EXPECT_MV_NEAR(log_blend(r1, r2, T(0)), r1, tol);
    EXPECT_MV_NEAR(log_blend(r1, r2, T(1)), r2, tol);
    EXPECT_MV_NEAR(log_blend(r1, r2, t), log_blend(r2, r1, T(1) - t), tol) << "rotor, case " << k;
    // Motors.
    const Motor<T> m1 = f1.motor(), m2 = f2.motor();
    EXPECT_MV_NEAR(log_blend(m1, m2, T(0)), m1, tol);
    EXPECT_MV_NEAR(log_blend(m1, m2, T(1)), m2, tol);
    EXPECT_MV_NEAR(log_blend(m1, m2, t), log_blend(m2, m1, T(1) - t), tol) << "motor, case " << k;
    ASSERT_TRUE(is_unit(log_blend(m1, m2, t), tol));
    // TRS versors.
    const Versor<T> v1 = f1.versor(), v2 = f2.versor();
    EXPECT_MV_NEAR(log_blend(v1, v2, T(0)), v1, tol);
    EXPECT_MV_NEAR(log_blend(v1, v2, T(1)), v2, tol);
    EXPECT_MV_NEAR(log_blend(v1, v2, t), log_blend(v2, v1, T(1) - t), tol) << "versor, case " << k;
    // Scale interpolates geometrically.
    EXPECT_NEAR(decompose(log_blend(v1, v2, t)).scale, std::pow(f1.scale, T(1) - t) * std::pow(f2.scale, t),
                tol * T(10));
  }
}

TYPED_TEST(Interpolation, LogBlendOfRotorsHasConstantAngularVelocity) {
  using T = TypeParam;
  const T tol = pick<T>(1e-13, 1e-5);
  Rng rng(0x60004 + sizeof(T));
  for (int k = 0; k < 500; ++k) {
    const Vec3<T> axis = random_unit<T>(rng);
    const T a1 = rng.uniform<T>(-3, 3);
    const T a2 = a1 + rng.uniform<T>(-3, 3);  // |a2 - a1| < pi: the short way
    const Rotor<T> r1 = rotor(axis, a1), r2 = rotor(axis, a2);
    for (int i = 0; i <= 4; ++i) {
      const T t = T(i) / T(4);
      EXPECT_MV_NEAR(log_blend(r1, r2, t), rotor(axis, a1 + t * (a2 - a1)), tol) << "case " << k << " t " << t;
    }
    // The same for motors about a fixed screw axis: the rotation angle is interpolated linearly.
    const Motor<T> m1 = translator(Vec3<T>(axis * T(2))) * r1;
    const Motor<T> m2 = translator(Vec3<T>(axis * T(4))) * r2;
    const Motor<T> mid = log_blend(m1, m2, T(0.5));
    EXPECT_MV_NEAR(mid, Motor<T>(translator(Vec3<T>(axis * T(3))) * rotor(axis, (a1 + a2) / 2)), tol * T(10));
  }
  // Slerp-like: equal steps in t give equal angles between consecutive rotors.
  const Rotor<T> r1 = rotor<T>(Vec3<T>(1, 1, 0), T(0.2)), r2 = rotor<T>(Vec3<T>(0, 1, 1), T(2.0));
  std::vector<T> steps;
  for (int i = 0; i < 8; ++i) {
    const Rotor<T> p = log_blend(r1, r2, T(i) / T(8)), q = log_blend(r1, r2, T(i + 1) / T(8));
    steps.push_back(T(2) * std::acos(std::min(T(1), scalar_product(q, reverse(p)))));
  }
  for (const T s : steps) EXPECT_NEAR(s, steps[0], pick<T>(1e-12, 1e-3));
  EXPECT_GT(steps[0], T(0.1));
}

TYPED_TEST(Interpolation, BlendWeightsAndErrors) {
  using T = TypeParam;
  const T tol = pick<T>(1e-12, 1e-5);
  Rng rng(0x60005 + sizeof(T));
  for (int k = 0; k < 200; ++k) {
    const auto f1 = random_similarity<T>(rng), f2 = random_similarity<T>(rng);
    const std::array<Motor<T>, 2> motors{f1.motor(), f2.motor()};
    const std::array<T, 2> first{T(1), T(0)}, second{T(0), T(1)};
    EXPECT_MV_NEAR(blend(std::span<const Motor<T>>(motors), std::span<const T>(first)), motors[0], tol);
    EXPECT_MV_NEAR(blend(std::span<const Motor<T>>(motors), std::span<const T>(second)), motors[1], tol);
    const std::array<Versor<T>, 2> versors{f1.versor(), f2.versor()};
    EXPECT_MV_NEAR(blend(std::span<const Versor<T>>(versors), std::span<const T>(first)), versors[0], tol);
    const std::array<Rotor<T>, 2> rotors{f1.rotor(), f2.rotor()};
    EXPECT_MV_NEAR(blend(std::span<const Rotor<T>>(rotors), std::span<const T>(second)), rotors[1], tol);
  }
  // Two rotors about one axis: the weighted sum of the angles.
  const std::array<Rotor<T>, 2> rs{rotor<T>(Vec3<T>(0, 0, 1), T(0.4)), rotor<T>(Vec3<T>(0, 0, 1), T(1.2))};
  const std::array<T, 2> w{T(0.25), T(0.75)};
  EXPECT_MV_NEAR(blend(std::span<const Rotor<T>>(rs), std::span<const T>(w)), rotor<T>(Vec3<T>(0, 0, 1), T(1.0)), tol);
  // Mismatched and empty spans.
  const std::array<T, 3> three{T(0.2), T(0.3), T(0.5)};
  EXPECT_THROW((void)blend(std::span<const Rotor<T>>(rs), std::span<const T>(three)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)blend(std::span<const Rotor<T>>(rs).first(1), std::span<const T>(w)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)blend(std::span<const Rotor<T>>(), std::span<const T>()), cgamesh::InvalidInputError);
  // A non-unit versor has no log.
  const std::array<Rotor<T>, 2> bad{rs[0], Rotor<T>(rs[1] * T(2))};
  EXPECT_THROW((void)blend(std::span<const Rotor<T>>(bad), std::span<const T>(w)), cgamesh::InvalidInputError);
}

}  // namespace
