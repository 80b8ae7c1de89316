// Conversions to and from quaternions, 4x4 matrices and dual quaternions.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class Convert : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Convert, FloatTypes);

template <class T>
using Mat4 = Eigen::Matrix<T, 4, 4>;

TYPED_TEST(Convert, RotorQuaternionRoundTrip) {
  using T = TypeParam;
  const T tol = pick<T>(1e-14, 1e-6);
  Rng rng(0x70001 + sizeof(T));
  for (int k = 0; k < 1000; ++k) {
    const auto f = random_similarity<T>(rng);
    const Eigen::Quaternion<T> q = f.quaternion();
    const Rotor<T> r = rotor(q);
    // The rotor of a quaternion is the rotor of the same axis and angle, with the same sign.
    EXPECT_MV_NEAR(r, f.rotor(), tol);
    const Eigen::Quaternion<T> back = to_quaternion(r);
    EXPECT_MAT_NEAR(Eigen::Matrix<T, 4, 1>(back.coeffs()), Eigen::Matrix<T, 4, 1>(q.coeffs()), tol);
    // Non-unit quaternions are normalised; -q gives -R.
    const Eigen::Quaternion<T> q3(q.coeffs() * T(-3));
    EXPECT_MV_NEAR(rotor(q3), -r, tol);
    // Same rotation of a point.
    const Vec3<T> x = random_vec3<T>(rng, -5, 5);
    EXPECT_MAT_NEAR(transform_point(r, x), Vec3<T>(q * x), tol * T(10));
    EXPECT_MAT_NEAR(Vec3<T>(to_quaternion(r) * x), Vec3<T>(q * x), tol * T(10));
  }
  // 90 degrees about z.
  const Eigen::Quaternion<T> qz(Eigen::AngleAxis<T>(std::numbers::pi_v<T> / 2, Vec3<T>::UnitZ()));
  EXPECT_MAT_NEAR(transform_point(rotor(qz), Vec3<T>(1, 0, 0)), Vec3<T>(0, 1, 0), tol);
  EXPECT_THROW((void)rotor(Eigen::Quaternion<T>(0, 0, 0, 0)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)rotor(Eigen::Quaternion<T>(std::numeric_limits<T>::quiet_NaN(), 0, 0, 1)),
               cgamesh::InvalidInputError);
}

TYPED_TEST(Convert, MatrixRoundTrip) {
  using T = TypeParam;
  const T tol = pick<T>(1e-11, 2e-4);
  Rng rng(0x70002 + sizeof(T));
  for (int k = 0; k < 1000; ++k) {
    const auto f = random_similarity<T>(rng);
    const Versor<T> v = f.versor();
    const Mat4<T> m = to_matrix(v);
    // The matrix is [s R, t; 0 0 0 1].
    Mat4<T> expected = Mat4<T>::Identity();
    expected.template topLeftCorner<3, 3>() = f.linear();
    expected.template topRightCorner<3, 1>() = f.t;
    EXPECT_MAT_NEAR(m, expected, tol);
    const Versor<T> w = versor_from_matrix(m);
    const Vec3<T> x = random_vec3<T>(rng, -5, 5);
    const Vec3<T> mx = (m * x.homogeneous()).template head<3>();
    EXPECT_MAT_NEAR(transform_point(w, x), transform_point(v, x), tol * T(10));
    EXPECT_MAT_NEAR(mx, transform_point(v, x), tol * T(10));
    // The versor itself comes back up to its sign (a matrix does not know the sign of R).
    const T sign = scalar_product(w, reverse(v)) < 0 ? T(-1) : T(1);
    EXPECT_MV_NEAR(Versor<T>(w * sign), v, tol * T(10));
  }
}

TYPED_TEST(Convert, MatrixRejectsNonSimilarities) {
  using T = TypeParam;
  Mat4<T> shear = Mat4<T>::Identity();
  shear(0, 1) = T(0.5);
  EXPECT_THROW((void)versor_from_matrix(shear), cgamesh::InvalidInputError);
  Mat4<T> nonuniform = Mat4<T>::Identity();
  nonuniform.diagonal() << 1, 2, 1, 1;
  EXPECT_THROW((void)versor_from_matrix(nonuniform), cgamesh::InvalidInputError);
  Mat4<T> mirror = Mat4<T>::Identity();
  mirror(2, 2) = T(-1);
  EXPECT_THROW((void)versor_from_matrix(mirror), cgamesh::InvalidInputError);
  EXPECT_THROW((void)versor_from_matrix(Mat4<T>(Mat4<T>::Identity() * T(-1))), cgamesh::InvalidInputError);
  Mat4<T> nan = Mat4<T>::Identity();
  nan(1, 3) = std::numeric_limits<T>::quiet_NaN();
  EXPECT_THROW((void)versor_from_matrix(nan), cgamesh::InvalidInputError);
  Mat4<T> projective = Mat4<T>::Identity();
  projective(3, 0) = T(0.1);
  EXPECT_THROW((void)versor_from_matrix(projective), cgamesh::InvalidInputError);
  EXPECT_THROW((void)versor_from_matrix(Mat4<T>(Mat4<T>::Zero())), cgamesh::InvalidInputError);
  // A uniform scale with translation is accepted.
  Mat4<T> ok = Mat4<T>::Identity();
  ok.template topLeftCorner<3, 3>() *= T(2);
  ok.template topRightCorner<3, 1>() << 1, 2, 3;
  EXPECT_MAT_NEAR(transform_point(versor_from_matrix(ok), Vec3<T>(1, 1, 1)), Vec3<T>(3, 4, 5), pick<T>(1e-14, 1e-5));
  // to_matrix rejects a versor that is not a similarity.
  EXPECT_THROW((void)to_matrix(Versor<T>()), cgamesh::InvalidInputError);
}

TYPED_TEST(Convert, DualQuaternionRoundTrip) {
  using T = TypeParam;
  const T tol = pick<T>(1e-12, 2e-5);
  Rng rng(0x70003 + sizeof(T));
  for (int k = 0; k < 1000; ++k) {
    const auto f = random_similarity<T>(rng);
    const Motor<T> m = f.motor();
    const DualQuaternion<T> dq = to_dual_quaternion(m);
    // Real part: the rotation quaternion; dual part: (1/2) t q.
    const Eigen::Quaternion<T> q = f.quaternion();
    EXPECT_MAT_NEAR(Eigen::Matrix<T, 4, 1>(dq.real.coeffs()), Eigen::Matrix<T, 4, 1>(q.coeffs()), tol);
    const Eigen::Quaternion<T> tq(T(0), f.t.x(), f.t.y(), f.t.z());
    EXPECT_MAT_NEAR(Eigen::Matrix<T, 4, 1>(dq.dual.coeffs()), Eigen::Matrix<T, 4, 1>((tq * q).coeffs() * T(0.5)), tol);
    // Back to the motor.
    EXPECT_MV_NEAR(motor(dq), m, tol);
    // The point map: q x q* + t.
    const Vec3<T> x = random_vec3<T>(rng, -5, 5);
    const Vec3<T> expected = Vec3<T>(dq.real * x) + f.t;
    EXPECT_MAT_NEAR(transform_point(motor(dq), x), expected, tol * T(10));
    // From a dual quaternion built by hand, with a non-unit scale.
    const DualQuaternion<T> hand{Eigen::Quaternion<T>(q.coeffs() * T(2)),
                                 Eigen::Quaternion<T>((tq * q).coeffs() * T(0.5) * T(2))};
    EXPECT_MAT_NEAR(transform_point(motor(hand), x), expected, tol * T(10));
  }
  const DualQuaternion<T> zero{Eigen::Quaternion<T>(0, 0, 0, 0), Eigen::Quaternion<T>(1, 0, 0, 0)};
  EXPECT_THROW((void)motor(zero), cgamesh::InvalidInputError);
  const DualQuaternion<T> nan{Eigen::Quaternion<T>(1, 0, 0, 0),
                              Eigen::Quaternion<T>(0, std::numeric_limits<T>::quiet_NaN(), 0, 0)};
  EXPECT_THROW((void)motor(nan), cgamesh::InvalidInputError);
}

}  // namespace
