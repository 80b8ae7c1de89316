// Exponential and logarithm of versors (paper section 2.5): closed forms against the Taylor
// references, round trips on random and edge-case versors, and blends through the log.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class ExpLog : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ExpLog, FloatTypes);

constexpr double kPi = std::numbers::pi;

/// log then exp of a unit versor of any kind must give it back, with no NaN on the way.
template <class T, BladeMask M>
::testing::AssertionResult round_trips(const Multivector<T, M>& v, T tol) {
  const auto g = log(v);
  if (!is_finite(g)) return ::testing::AssertionFailure() << "log has a NaN: " << to_string(g);
  const auto back = exp(g);
  static_assert(decltype(back)::mask == M, "exp(log(V)) has the type of V");
  return mv_near(back, v, tol);
}

/// The generator of x -> s R(axis, angle) x + t to first order, for near-identity versors.
template <class T>
SimilarityGenerator<T> first_order_generator(const Vec3<T>& t, const Vec3<T>& axis, T angle, T scale) {
  const Vec3<T> w = axis * angle;  // rotation vector; Br = -(1/2) w I3
  return SimilarityGenerator<T>({T(-0.5) * w.z(), T(0.5) * w.y(), T(-0.5) * w.x(), T(-0.5) * t.x(), T(-0.5) * t.y(),
                                 T(-0.5) * t.z(), T(-0.5) * std::log(scale)});
}

// ---------------------------------------------------------------- TRS versors

TEST(ExpLogVersor, RoundTripOnRandomSimilarities) {
  Rng rng(0x10001);
  for (int k = 0; k < 10000; ++k) {
    const auto f = random_similarity<double>(rng);
    const Versor<double> v = f.versor();
    ASSERT_TRUE(round_trips(v, 1e-12)) << "case " << k << " angle " << f.angle << " scale " << f.scale;
  }
}

TEST(ExpLogVersor, RoundTripOnRandomSimilaritiesFloat) {
  Rng rng(0x10002);
  for (int k = 0; k < 1000; ++k) {
    const auto f = random_similarity<float>(rng);
    ASSERT_TRUE(round_trips(f.versor(), 2e-5f)) << "case " << k << " angle " << f.angle;
  }
}

TEST(ExpLogVersor, NearIdentity) {
  Rng rng(0x10003);
  for (int k = 0; k < 2000; ++k) {
    const Vec3<double> axis = random_unit<double>(rng);
    const double angle = rng.log_uniform(1e-9, 1e-5);
    const Vec3<double> t = random_unit<double>(rng) * 1e-9;
    const double s = 1.0 + rng.uniform(-1e-9, 1e-9);
    const Versor<double> v = similarity(t, rotor(axis, angle), s);
    ASSERT_TRUE(round_trips(v, 1e-15)) << "case " << k;
    // log agrees with the series and, to first order, with the parameters.
    const auto g = log(v);
    if (k < 200) {
      EXPECT_MV_NEAR(g, log_series(v), 1e-15);
    }
    EXPECT_MV_NEAR(g, first_order_generator(t, axis, angle, s), 1e-14);
  }
  // Exactly the identity: log is exactly zero.
  EXPECT_MV_NEAR(log(Versor<double>(Scalar<double>({1.0}))), SimilarityGenerator<double>(), 0.0);
}

TEST(ExpLogVersor, NearHalfTurn) {
  Rng rng(0x10004);
  for (int k = 0; k < 2000; ++k) {
    const auto f0 = random_similarity<double>(rng);
    const double angle = kPi - rng.uniform(0.0, 1e-7);
    const Versor<double> v = similarity(f0.t, rotor(f0.axis, angle), f0.scale);
    ASSERT_TRUE(round_trips(v, 1e-12)) << "case " << k;
    // The rotation part of the log is -(angle/2) u I3.
    const auto g = log(v);
    EXPECT_NEAR(std::hypot(g[0], g[1], g[2]), angle / 2, 1e-12);
  }
  // Exactly pi.
  const Versor<double> v = similarity<double>(Vec3<double>(1, 2, 3), rotor<double>(Vec3<double>(0, 1, 0), kPi), 2.0);
  EXPECT_TRUE(round_trips(v, 1e-12));
  EXPECT_TRUE(round_trips(Versor<double>(rotor<double>(Vec3<double>(1, 0, 0), kPi)), 1e-15));
}

TYPED_TEST(ExpLog, PureTranslationRotationDilation) {
  using T = TypeParam;
  const T tol = pick<T>(1e-13, 2e-6);
  Rng rng(0x10005 + sizeof(T));
  for (int k = 0; k < 1000; ++k) {
    const Vec3<T> t = random_vec3<T>(rng, -10, 10);
    const Vec3<T> axis = random_unit<T>(rng);
    const T angle = rng.uniform<T>(0, std::numbers::pi_v<T>);
    const T s = rng.log_uniform<T>(T(0.2), T(5));
    // Pure translation: R = 1, s = 1. log = -(1/2) t ^ einf exactly; no NaN.
    const Versor<T> vt(translator(t));
    ASSERT_TRUE(round_trips(vt, tol)) << "translation, case " << k;
    EXPECT_MV_NEAR(log(vt), first_order_generator(t, axis, T(0), T(1)), tol);
    // Pure rotation.
    const Versor<T> vr(rotor(axis, angle));
    ASSERT_TRUE(round_trips(vr, tol)) << "rotation, case " << k;
    EXPECT_MV_NEAR(log(vr), first_order_generator(Vec3<T>(Vec3<T>::Zero()), axis, angle, T(1)), tol);
    // Pure dilation: log = -(ln s / 2) einf^eo.
    const Versor<T> vd(dilator(s));
    ASSERT_TRUE(round_trips(vd, tol)) << "dilation, case " << k;
    EXPECT_MV_NEAR(log(vd), first_order_generator(Vec3<T>(Vec3<T>::Zero()), axis, T(0), s), tol);
  }
}

// ---------------------------------------------------------------- motors and rotors

TYPED_TEST(ExpLog, MotorRoundTrips) {
  using T = TypeParam;
  const T tol = pick<T>(1e-12, 2e-5);
  Rng rng(0x20001 + sizeof(T));
  for (int k = 0; k < 2000; ++k) {
    const auto f = random_similarity<T>(rng);
    ASSERT_TRUE(round_trips(f.motor(), tol)) << "case " << k;
    // Pure translation and pure rotation motors.
    ASSERT_TRUE(round_trips(Motor<T>(translator(f.t)), tol)) << "case " << k;
    ASSERT_TRUE(round_trips(Motor<T>(f.rotor()), tol)) << "case " << k;
  }
  // Near identity and near a half turn.
  for (int k = 0; k < 1000; ++k) {
    const Vec3<T> axis = random_unit<T>(rng);
    const T small = rng.log_uniform<T>(T(1e-9), T(1e-5));
    const Motor<T> m = translator(Vec3<T>(random_unit<T>(rng) * T(1e-9))) * rotor(axis, small);
    ASSERT_TRUE(round_trips(m, pick<T>(1e-15, 1e-7))) << "case " << k;
    const Motor<T> h = translator(random_vec3<T>(rng, -10, 10)) * rotor(axis, std::numbers::pi_v<T> - small);
    ASSERT_TRUE(round_trips(h, tol)) << "case " << k;
  }
  EXPECT_MV_NEAR(log(Motor<T>(Scalar<T>({T(1)}))), MotorGenerator<T>(), T(0));
}

TYPED_TEST(ExpLog, RotorRoundTrips) {
  using T = TypeParam;
  const T tol = pick<T>(1e-14, 1e-6);
  Rng rng(0x30001 + sizeof(T));
  for (int k = 0; k < 2000; ++k) {
    const Vec3<T> axis = random_unit<T>(rng);
    // Principal angles up to (almost) 2 pi: the rotor's sign is kept.
    const T angle = rng.uniform<T>(0, T(2) * std::numbers::pi_v<T> - T(1e-2));
    const Rotor<T> r = rotor(axis, angle);
    ASSERT_TRUE(round_trips(r, tol)) << "case " << k << " angle " << angle;
    const RotationGenerator<T> g = log(r);
    EXPECT_MV_NEAR(g, project<mask::rotation_generator>(first_order_generator(Vec3<T>(Vec3<T>::Zero()), axis, angle, T(1))),
                   tol * T(10));
    // Near identity and near pi.
    const T small = rng.log_uniform<T>(T(1e-9), T(1e-5));
    ASSERT_TRUE(round_trips(rotor(axis, small), tol)) << "case " << k;
    ASSERT_TRUE(round_trips(rotor(axis, std::numbers::pi_v<T> - small), tol)) << "case " << k;
  }
  EXPECT_MV_NEAR(log(Rotor<T>(Scalar<T>({T(1)}))), RotationGenerator<T>(), T(0));
}

TYPED_TEST(ExpLog, LogOfNonUnitThrows) {
  using T = TypeParam;
  const Rotor<T> r = rotor<T>(Vec3<T>(1, 2, 3), T(0.5));
  EXPECT_THROW((void)log(Rotor<T>(r * T(2))), cgamesh::InvalidInputError);
  EXPECT_THROW((void)log(Rotor<T>()), cgamesh::InvalidInputError);
  const Motor<T> m = translator<T>(Vec3<T>(1, 0, 0)) * r;
  EXPECT_THROW((void)log(Motor<T>(m * T(0.5))), cgamesh::InvalidInputError);
  EXPECT_THROW((void)log(Motor<T>()), cgamesh::InvalidInputError);
  Rotor<T> nan_rotor = r;
  nan_rotor[1] = std::numeric_limits<T>::quiet_NaN();
  EXPECT_THROW((void)log(nan_rotor), cgamesh::InvalidInputError);
  // Versors: not similarities.
  EXPECT_THROW((void)log(Versor<T>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)log(Versor<T>(T(1) + basis_blade<T, blade::e2 | blade::eo>(T(0.5)))), cgamesh::InvalidInputError);
  // Unit ones do not throw.
  EXPECT_NO_THROW((void)log(r));
  EXPECT_NO_THROW((void)log(m));
}

// ---------------------------------------------------------------- closed forms vs series

TYPED_TEST(ExpLog, ClosedFormExpMatchesSeries) {
  using T = TypeParam;
  const T tol = pick<T>(1e-13, 1e-5);
  Rng rng(0x40001 + sizeof(T));
  // exp_series is costly (dense products): a few hundred generators in all.
  for (int k = 0; k < 50; ++k) {
    const auto gs = random_mv<SimilarityGenerator<T>>(rng, -1, 1);
    const Versor<T> v = exp(gs);
    EXPECT_MV_NEAR(v, exp_series(gs), tol) << "similarity generator " << k;
    EXPECT_NEAR(norm_squared(v), T(1), tol * 10);
    const auto gm = random_mv<MotorGenerator<T>>(rng, -2, 2);
    EXPECT_MV_NEAR(exp(gm), exp_series(gm), tol) << "motor generator " << k;
    const auto gr = random_mv<RotationGenerator<T>>(rng, -2, 2);
    EXPECT_MV_NEAR(exp(gr), exp_series(gr), tol) << "rotation generator " << k;
    // Small generators (series branches of the closed form).
    const auto tiny = random_mv<SimilarityGenerator<T>>(rng, T(-1e-5), T(1e-5));
    EXPECT_MV_NEAR(exp(tiny), exp_series(tiny), pick<T>(1e-15, 1e-7)) << "tiny generator " << k;
  }
}

TYPED_TEST(ExpLog, GeneralBivectorExpMatchesSeries) {
  using T = TypeParam;
  const T tol = pick<T>(1e-12, 1e-5);
  Rng rng(0x40002 + sizeof(T));
  for (int k = 0; k < 50; ++k) {
    const auto b = random_mv<Bivector<T>>(rng, -1, 1);
    const Versor<T> v = exp(b);
    EXPECT_MV_NEAR(v, exp_series(b), tol) << "case " << k;
    EXPECT_MV_NEAR(v * reverse(v), Scalar<T>({T(1)}), tol * 10) << "case " << k;
  }
  // Degenerate splits: simple bivectors (B ^ B = 0) and the zero bivector.
  const Bivector<T> simple = Bivector<T>(euclidean<T>(1, 0, 0) ^ euclidean<T>(0, 1, 0)) * T(0.7);
  EXPECT_MV_NEAR(exp(simple), exp_series(simple), tol);
  EXPECT_MV_NEAR(exp(Bivector<T>()), Scalar<T>({T(1)}), T(0));
  const Bivector<T> null_biv(basis_blade<T, blade::e1inf>(T(3)));
  EXPECT_MV_NEAR(exp(null_biv), T(1) + basis_blade<T, blade::e1inf>(T(3)), tol);
}

TEST(ExpLogSeries, LogMatchesLogSeriesNearIdentity) {
  Rng rng(0x50001);
  for (int k = 0; k < 100; ++k) {
    const auto g = random_mv<SimilarityGenerator<double>>(rng, -0.05, 0.05);
    const Versor<double> v = exp(g);
    const auto l = log(v);
    EXPECT_MV_NEAR(l, g, 1e-14) << "case " << k;
    EXPECT_MV_NEAR(l, log_series(v), 1e-13) << "case " << k;
    const auto gm = random_mv<MotorGenerator<double>>(rng, -0.05, 0.05);
    const Motor<double> m = exp(gm);
    EXPECT_MV_NEAR(log(m), log_series(m), 1e-13) << "case " << k;
  }
  EXPECT_THROW((void)log_series(Versor<double>(Scalar<double>({3.0}))), cgamesh::InvalidInputError);
  EXPECT_MV_NEAR(exp_series(log_series(dilator(1.2))), dilator(1.2), 1e-14);
}

// ---------------------------------------------------------------- blends through the log

TEST(ExpLogBlend, TranslatorAndIdentityBlendToHalfTheTranslation) {
  const Motor<double> t2(translator<double>(Vec3<double>(2, 0, 0)));
  const Motor<double> id(Scalar<double>({1.0}));
  const auto sum = log(t2) * 0.5 + log(id) * 0.5;
  ASSERT_TRUE(all_finite(sum));
  EXPECT_MV_NEAR(exp(sum), translator<double>(Vec3<double>(1, 0, 0)), 1e-15);
  const std::array<Motor<double>, 2> motors{t2, id};
  const std::array<double, 2> weights{0.5, 0.5};
  const Motor<double> b = blend(std::span<const Motor<double>>(motors), std::span<const double>(weights));
  EXPECT_MV_NEAR(b, translator<double>(Vec3<double>(1, 0, 0)), 1e-15);
  // The same with TRS versors, and with a rotation: exp(w1 log T + w2 log R) is finite and a
  // screw of half the translation and half the angle.
  const std::array<Versor<double>, 2> versors{Versor<double>(t2), Versor<double>(rotor<double>(Vec3<double>(0, 0, 1), 1.0))};
  const Versor<double> bv = blend(std::span<const Versor<double>>(versors), std::span<const double>(weights));
  ASSERT_TRUE(all_finite(bv));
  EXPECT_NEAR(norm_squared(bv), 1.0, 1e-14);
  const SimilarityParts<double> p = decompose(bv);
  EXPECT_NEAR(p.scale, 1.0, 1e-14);
  EXPECT_MV_NEAR(p.rotation, rotor<double>(Vec3<double>(0, 0, 1), 0.5), 1e-14);
  // Translation of exp(0.5 (v ^ einf ... )): the screw flow of v = (1, 0, 0), w = (0, 0, 0.5)
  // for unit time: t = F(A) v with F(A) v = (sin(w)/w, (1 - cos w)/w, 0) |v|.
  EXPECT_MAT_NEAR(p.translation, Vec3<double>(std::sin(0.5) / 0.5, (1 - std::cos(0.5)) / 0.5, 0), 1e-14);
  // A versor blend of a pure dilation and the identity: half the log-scale.
  const std::array<Versor<double>, 2> dil{Versor<double>(dilator(4.0)), Versor<double>(Scalar<double>({1.0}))};
  EXPECT_MV_NEAR(blend(std::span<const Versor<double>>(dil), std::span<const double>(weights)), dilator(2.0), 1e-14);
}

}  // namespace
