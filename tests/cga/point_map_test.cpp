// PointMap: a versor's sandwich on points as a 5x5 (or affine 3x4) matrix.

#include <cstddef>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class PointMaps : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(PointMaps, FloatTypes);

template <class T>
std::vector<T> random_points(Rng& rng, std::size_t n, T range) {
  std::vector<T> xs(3 * n);
  for (auto& x : xs) x = rng.uniform<T>(-range, range);
  return xs;
}

template <class T>
Vec3<T> point_at(const std::vector<T>& xs, std::size_t i) {
  return Vec3<T>(xs[3 * i], xs[3 * i + 1], xs[3 * i + 2]);
}

TYPED_TEST(PointMaps, SimilaritiesAreAffineAndMatchTheSandwich) {
  using T = TypeParam;
  const T tol = pick<T>(1e-12, 5e-5);
  Rng rng(0x80001 + sizeof(T));
  for (int k = 0; k < 5; ++k) {
    const auto f = random_similarity<T>(rng);
    const Versor<T> v = f.versor();
    const PointMap<T> map(v);
    ASSERT_TRUE(map.is_affine()) << "case " << k;
    // The affine matrix is [s R | t].
    Eigen::Matrix<T, 3, 4> expected;
    expected << f.linear(), f.t;
    EXPECT_MAT_NEAR(map.affine_matrix(), expected, tol);
    const std::size_t n = 1000;
    const std::vector<T> in = random_points<T>(rng, n, T(10));
    std::vector<T> out(in.size());
    map.apply(in, out);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3<T> x = point_at(in, i);
      const Vec3<T> want = transform_point(v, x);
      ASSERT_TRUE(mat_near(point_at(out, i), want, tol * T(10))) << "case " << k << " point " << i;
      ASSERT_TRUE(mat_near(map(x), want, tol * T(10))) << "case " << k << " point " << i;
    }
    // In place (out aliases in).
    std::vector<T> inplace = in;
    map.apply(inplace, inplace);
    EXPECT_EQ(inplace, out);
  }
  // Motors, rotors and translators too; a scaled versor is the same map.
  const auto f = random_similarity<T>(rng);
  EXPECT_TRUE(PointMap<T>(f.motor()).is_affine());
  EXPECT_TRUE(PointMap<T>(f.rotor()).is_affine());
  EXPECT_TRUE(PointMap<T>(Versor<T>(f.versor() * T(-4))).is_affine());
  EXPECT_MAT_NEAR(PointMap<T>(Versor<T>(f.versor() * T(-4))).affine_matrix(), PointMap<T>(f.versor()).affine_matrix(),
                  tol);
}

TYPED_TEST(PointMaps, TheFiveByFiveMatrixIsTheSandwichOnBasisVectors) {
  using T = TypeParam;
  Rng rng(0x80002 + sizeof(T));
  const auto v = random_similarity<T>(rng).versor();
  const PointMap<T> map(v);
  for (unsigned j = 0; j < 5; ++j) {
    Vector<T> e;
    e[j] = T(1);
    const Vector<T> y = sandwich(v, e);
    for (unsigned i = 0; i < 5; ++i) EXPECT_NEAR(map.matrix()(i, j), y[i], pick<T>(1e-12, 1e-4)) << i << "," << j;
  }
}

TYPED_TEST(PointMaps, MotorClosedFormIsThePointMapOfTheMotor) {
  using T = TypeParam;
  const T tol = pick<T>(1e-12, 5e-5);
  Rng rng(0x80003 + sizeof(T));
  for (int k = 0; k < 200; ++k) {
    const auto f = random_similarity<T>(rng);
    // Composed both ways round, at any scale and sign (the map of s M is the map of M).
    const auto g = random_similarity<T>(rng);
    const T s = (k % 2 ? T(-1) : T(1)) * rng.log_uniform<T>(T(0.01), T(100));
    const Motor<T> m = k % 3 == 0 ? f.motor() : Motor<T>(f.motor() * g.motor() * s);
    const Eigen::Matrix<T, 3, 4> a = motor_affine_matrix(m);
    EXPECT_MAT_NEAR(a, PointMap<T>(m).affine_matrix(), tol * T(10)) << "case " << k;
    if (k % 3 == 0) {
      Eigen::Matrix<T, 3, 4> expected;
      expected << f.linear() / f.scale, f.t;
      EXPECT_MAT_NEAR(a, expected, tol * T(10)) << "case " << k;
    }
  }
  // Half turns (the rotor's scalar part is zero), pure translations and the identity.
  const Vec3<T> t(T(1), T(-2), T(3));
  for (const Vec3<T>& axis : {Vec3<T>(Vec3<T>::UnitX()), Vec3<T>(Vec3<T>::UnitY()), Vec3<T>(T(0.6), T(0), T(0.8))}) {
    const Motor<T> m(translator(t) * rotor(axis, std::numbers::pi_v<T>));
    EXPECT_MAT_NEAR(motor_affine_matrix(m), PointMap<T>(m).affine_matrix(), tol);
  }
  EXPECT_MAT_NEAR(motor_affine_matrix(Motor<T>(translator(t))), PointMap<T>(translator(t)).affine_matrix(), tol);
  const Motor<T> one(basis_blade<T, cgamesh::cga::blade::scalar>());
  EXPECT_MAT_NEAR(motor_affine_matrix(one), Eigen::Matrix<T, 3, 4>(Eigen::Matrix<T, 3, 4>::Identity()), T(0));
  // Without a rotor part it is no motor.
  EXPECT_THROW((void)motor_affine_matrix(Motor<T>(basis_blade<T, cgamesh::cga::blade::e1inf>())),
               cgamesh::InvalidInputError);
  Motor<T> nan = one;
  nan.template at<cgamesh::cga::blade::e12>() = std::numeric_limits<T>::quiet_NaN();
  EXPECT_THROW((void)motor_affine_matrix(nan), cgamesh::InvalidInputError);
}

TYPED_TEST(PointMaps, NonSimilaritiesKeepTheRationalForm) {
  using T = TypeParam;
  const T tol = pick<T>(1e-12, 1e-4);
  // A transversion: exp(0.3 e1^eo) = 1 + 0.3 e1^eo (the generator squares to zero).
  const Dense<T> k_dense = exp_series(basis_blade<T, blade::e1 | blade::eo>(T(0.3)));
  EXPECT_MV_NEAR(k_dense, T(1) + basis_blade<T, blade::e1 | blade::eo>(T(0.3)), pick<T>(1e-15, 1e-7));
  const Versor<T> transversion = project<mask::versor>(k_dense);
  // Also composed with a translation and a rotation: still not a similarity.
  const Versor<T> composed =
      Versor<T>(translator<T>(Vec3<T>(1, -2, 0.5)) * rotor<T>(Vec3<T>(0, 1, 1), T(0.4)) * transversion);
  // An odd versor: the inversion in the unit sphere, x -> x / |x|^2.
  const Vector<T> inversion = sphere<T>(Vec3<T>(0, 0, 0), T(1));
  Rng rng(0x80003 + sizeof(T));
  for (const Dense<T>& v : {Dense<T>(transversion), Dense<T>(composed)}) {
    const PointMap<T> map(v);
    EXPECT_FALSE(map.is_affine());
    const std::vector<T> in = random_points<T>(rng, 1000, T(0.5));
    std::vector<T> out(in.size());
    map.apply(in, out);
    for (std::size_t i = 0; i < 1000; ++i) {
      const Vec3<T> x = point_at(in, i);
      const Vec3<T> want = transform_point(v, x);
      ASSERT_TRUE(mat_near(map(x), want, tol)) << "point " << i;
      ASSERT_TRUE(mat_near(point_at(out, i), want, tol)) << "point " << i;
    }
    // Not affine indeed: midpoints are not preserved.
    const Vec3<T> a(T(0.5), 0, 0), b(T(-0.5), T(0.2), 0);
    EXPECT_GT((map(Vec3<T>((a + b) / T(2))) - (map(a) + map(b)) / T(2)).norm(), T(1e-3));
  }
  const PointMap<T> inv_map(inversion);
  EXPECT_FALSE(inv_map.is_affine());
  for (int i = 0; i < 100; ++i) {
    const Vec3<T> x = random_vec3<T>(rng, -3, 3);
    if (x.norm() < T(0.1)) continue;
    EXPECT_MAT_NEAR(inv_map(x), Vec3<T>(x / x.squaredNorm()), tol * T(10));
    EXPECT_MAT_NEAR(inv_map(x), transform_point(inversion, x), tol * T(10));
  }
  // The inversion sends the origin to infinity.
  EXPECT_THROW((void)inv_map(Vec3<T>(0, 0, 0)), cgamesh::InvalidInputError);
}

TYPED_TEST(PointMaps, ApplyRejectsMismatchedSizes) {
  using T = TypeParam;
  Rng rng(5);
  const PointMap<T> map(random_similarity<T>(rng).versor());
  std::vector<T> in(9, T(1)), out6(6), out9(9), in8(8), out8(8);
  EXPECT_THROW(map.apply(in, out6), cgamesh::InvalidInputError);
  EXPECT_THROW(map.apply(in8, out8), cgamesh::InvalidInputError);
  EXPECT_NO_THROW(map.apply(in, out9));
  const PointMap<T> nonaffine(Versor<T>(T(1) + basis_blade<T, blade::e2 | blade::eo>(T(0.2))));
  EXPECT_THROW(nonaffine.apply(in, out6), cgamesh::InvalidInputError);
  // A non-invertible versor cannot make a map.
  EXPECT_THROW((void)PointMap<T>(eo<T>()), cgamesh::InvalidInputError);
  // Empty input is fine.
  EXPECT_NO_THROW(map.apply(std::span<const T>(), std::span<T>()));
}

}  // namespace
