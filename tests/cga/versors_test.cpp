// Versors (paper section 2.4, eq. 8-14): orientation of rotors, order of composition,
// transformation of lines, circles, spheres and planes in outer form, decomposition.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class Versors : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Versors, FloatTypes);

TYPED_TEST(Versors, RotationIsRightHanded) {
  using T = TypeParam;
  const T tol = pick<T>(1e-15, 1e-6);
  const Rotor<T> r = rotor<T>(Vec3<T>(0, 0, 1), std::numbers::pi_v<T> / 2);
  // eq. (8): R = cos(pi/4) - sin(pi/4) e3 I3 = (1 - e12) / sqrt(2).
  EXPECT_MV_NEAR(r, Rotor<T>({std::sqrt(T(0.5)), -std::sqrt(T(0.5)), 0, 0}), tol);
  EXPECT_MV_NEAR(sandwich(r, euclidean<T>(1, 0, 0)), euclidean<T>(0, 1, 0), tol);
  EXPECT_MV_NEAR(sandwich(r, euclidean<T>(0, 1, 0)), euclidean<T>(-1, 0, 0), tol);
  EXPECT_MV_NEAR(sandwich(r, euclidean<T>(0, 0, 1)), euclidean<T>(0, 0, 1), tol);
  EXPECT_MV_NEAR(sandwich(r, up(Vec3<T>(1, 0, 0))), up(Vec3<T>(0, 1, 0)), tol);
  // eo and einf are fixed by rotations.
  EXPECT_MV_NEAR(sandwich(r, eo<T>()), eo<T>(), tol);
  EXPECT_MV_NEAR(sandwich(r, einf<T>()), einf<T>(), tol);
  // Same as Eigen's right-handed AngleAxis, about each axis.
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3<T> u = Vec3<T>::Unit(axis);
    const T angle = T(0.7);
    const Vec3<T> x(T(0.3), T(-1.2), T(2));
    EXPECT_MAT_NEAR(transform_point(rotor(u, angle), x), Vec3<T>(Eigen::AngleAxis<T>(angle, u) * x), tol * 10);
  }
  // The axis length does not matter, and (axis, angle) ~ (-axis, -angle).
  EXPECT_MV_NEAR(rotor<T>(Vec3<T>(0, 0, 5), T(1)), rotor<T>(Vec3<T>(0, 0, 1), T(1)), tol);
  EXPECT_MV_NEAR(rotor<T>(Vec3<T>(1, 2, 3), T(1)), rotor<T>(Vec3<T>(-1, -2, -3), T(-1)), tol);
  // A full turn is -1 (same rotation, opposite rotor).
  EXPECT_MV_NEAR(rotor<T>(Vec3<T>(1, 2, 3), 2 * std::numbers::pi_v<T>), Scalar<T>({T(-1)}), tol * 10);
}

TYPED_TEST(Versors, TranslatorAndDilatorOnPoints) {
  using T = TypeParam;
  const T tol = pick<T>(1e-14, 1e-5);
  const Vec3<T> x(1, 2, 3);
  // eq. (10): T = 1 - t einf / 2.
  EXPECT_MV_NEAR(translator<T>(Vec3<T>(2, -4, 6)), Translator<T>({1, -1, 2, -3}), T(0));
  EXPECT_MAT_NEAR(transform_point(translator<T>(Vec3<T>(2, -4, 6)), x), Vec3<T>(3, -2, 9), tol);
  // The origin maps to the translation vector, einf is fixed.
  EXPECT_MV_NEAR(unit_sandwich(translator<T>(Vec3<T>(2, -4, 6)), eo<T>()), up(Vec3<T>(2, -4, 6)), tol);
  EXPECT_MV_NEAR(unit_sandwich(translator<T>(Vec3<T>(2, -4, 6)), einf<T>()), einf<T>(), tol);
  // Dilator: unit norm, scales about the origin, D(s1) D(s2) = D(s1 s2).
  const Dilator<T> d = dilator(T(2.5));
  EXPECT_NEAR(norm_squared(d), T(1), tol);
  EXPECT_MAT_NEAR(transform_point(d, x), Vec3<T>(2.5, 5, 7.5), tol);
  EXPECT_MV_NEAR(dilator(T(2)) * dilator(T(3)), dilator(T(6)), tol);
  EXPECT_MV_NEAR(dilator(T(1)), Scalar<T>({T(1)}), T(0));
  // D eo ~D is a multiple of eo: the origin is fixed.
  const Vector<T> o = unit_sandwich(d, eo<T>());
  EXPECT_MV_NEAR(o, eo<T>() * o.template get<blade::eo>(), tol);
}

TYPED_TEST(Versors, CompositionAppliesTheRightFactorFirst) {
  using T = TypeParam;
  const T tol = pick<T>(1e-11, 2e-4);
  // eq. (14): M = M2 M1 applies M1 first. Translate by (1,0,0), then rotate 90deg about e3:
  // (0,0,0) -> (1,0,0) -> (0,1,0). The other order would give (1,0,0).
  const Translator<T> m1 = translator<T>(Vec3<T>(1, 0, 0));
  const Rotor<T> m2 = rotor<T>(Vec3<T>(0, 0, 1), std::numbers::pi_v<T> / 2);
  const Motor<T> m = m2 * m1;
  EXPECT_MAT_NEAR(transform_point(m, Vec3<T>(0, 0, 0)), Vec3<T>(0, 1, 0), tol);
  EXPECT_MAT_NEAR(transform_point(Motor<T>(m1 * m2), Vec3<T>(0, 0, 0)), Vec3<T>(1, 0, 0), tol);
  // Random similarities: the composition is the composition of the matrix maps.
  Rng rng(31 + sizeof(T));
  for (int k = 0; k < 500; ++k) {
    const auto f1 = random_similarity<T>(rng), f2 = random_similarity<T>(rng);
    const Versor<T> v = f2.versor() * f1.versor();
    const Vec3<T> x = random_vec3<T>(rng, -5, 5);
    const Vec3<T> expected = f2(f1(x));
    EXPECT_MAT_NEAR(transform_point(v, x), expected, tol * T(10));
    EXPECT_MAT_NEAR(transform_point(f2.versor(), transform_point(f1.versor(), x)), expected, tol * T(10));
    const Motor<T> mm = f2.motor() * f1.motor();
    Similarity<T> r1 = f1, r2 = f2;
    r1.scale = r2.scale = T(1);
    EXPECT_MAT_NEAR(transform_point(mm, x), Vec3<T>(r2(r1(x))), tol * T(10));
  }
}

TYPED_TEST(Versors, OuterFormsTransformLikeTheirPoints) {
  using T = TypeParam;
  const T tol = pick<T>(1e-10, 5e-3);
  Rng rng(41 + sizeof(T));
  for (int k = 0; k < 300; ++k) {
    const auto f = random_similarity<T>(rng);
    const Versor<T> v = f.versor();
    const Vec3<T> a = random_vec3<T>(rng, -3, 3), b = random_vec3<T>(rng, -3, 3), c = random_vec3<T>(rng, -3, 3),
                  d = random_vec3<T>(rng, -3, 3);
    if ((b - a).cross(c - a).norm() < T(1)) continue;
    {
      const auto [got, want] = normalise_pair(sandwich(v, line_through(a, b)), line_through(f(a), f(b)));
      EXPECT_MV_NEAR(got, want, tol) << "line, case " << k;
    }
    {
      const auto [got, want] = normalise_pair(sandwich(v, circle_through(a, b, c)), circle_through(f(a), f(b), f(c)));
      EXPECT_MV_NEAR(got, want, tol) << "circle, case " << k;
    }
    {
      const auto [got, want] = normalise_pair(sandwich(v, plane_through(a, b, c)), plane_through(f(a), f(b), f(c)));
      EXPECT_MV_NEAR(got, want, tol) << "plane, case " << k;
    }
    if (std::abs((b - a).cross(c - a).dot(d - a)) > T(1)) {
      const auto [got, want] =
          normalise_pair(sandwich(v, sphere_through(a, b, c, d)), sphere_through(f(a), f(b), f(c), f(d)));
      EXPECT_MV_NEAR(got, want, tol) << "sphere, case " << k;
    }
    // The sandwich keeps grades: a trivector stays a trivector.
    static_assert(decltype(sandwich(v, line_through(a, b)))::mask == mask::trivector);
  }
}

TYPED_TEST(Versors, DecomposeRecoversTheParts) {
  using T = TypeParam;
  const T tol = pick<T>(1e-11, 2e-4);
  Rng rng(51 + sizeof(T));
  for (int k = 0; k < 1000; ++k) {
    const auto f = random_similarity<T>(rng);
    const Rotor<T> r = f.rotor();
    // Any positive multiple of the versor.
    const Versor<T> v = f.versor() * rng.uniform<T>(T(0.5), T(2));
    const SimilarityParts<T> p = decompose(v);
    EXPECT_MAT_NEAR(p.translation, f.t, tol);
    EXPECT_NEAR(p.scale, f.scale, tol * f.scale);
    const T sign = scalar_product(p.rotation, reverse(r)) < 0 ? T(-1) : T(1);
    EXPECT_MV_NEAR(p.rotation, Rotor<T>(r * sign), tol);
    EXPECT_NEAR(norm_squared(p.rotation), T(1), tol);
    // Motors.
    const SimilarityParts<T> pm = decompose(f.motor());
    EXPECT_MAT_NEAR(pm.translation, f.t, tol);
    EXPECT_EQ(pm.scale, T(1));
    EXPECT_MV_NEAR(pm.rotation, r, tol);
  }
}

TYPED_TEST(Versors, DecomposeRejectsNonSimilarities) {
  using T = TypeParam;
  EXPECT_THROW((void)decompose(Versor<T>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)decompose(Motor<T>()), cgamesh::InvalidInputError);
  // A pure translator read as a motor has a rotation part (1); but a motor without scalar or
  // rotation blades has none.
  EXPECT_THROW((void)decompose(Motor<T>(Translator<T>({0, 1, 2, 3}))), cgamesh::InvalidInputError);
  // A transversion 1 + a e1^eo (a conformal map that is not a similarity: it moves infinity).
  const Versor<T> transversion(T(1) + basis_blade<T, blade::e1 | blade::eo>(T(0.3)));
  EXPECT_THROW((void)decompose(transversion), cgamesh::InvalidInputError);
  // -D(s) maps einf to a positive multiple too: that is fine; but an even versor with negative
  // <V ~V> (e.g. e1 e-) is not a similarity.
  EXPECT_THROW((void)decompose(Versor<T>(euclidean<T>(1, 0, 0) * e_minus<T>())), cgamesh::InvalidInputError);
}

}  // namespace
