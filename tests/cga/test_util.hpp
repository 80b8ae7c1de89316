#pragma once
// Shared helpers of the CGA tests: a fixed-seed random generator (portable: no std::
// distributions, whose output differs between standard libraries), random multivectors,
// versors and points, and coefficient-wise comparisons that name the offending blades.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cgamesh/cga.hpp"

namespace cgatest {

using namespace cgamesh::cga;  // NOLINT(google-build-using-namespace)

/// Deterministic generator: mt19937_64 with a fixed seed and hand-rolled uniform doubles.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1) with 53 random bits.
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi].
  template <class T>
  T uniform(T lo, T hi) {
    return static_cast<T>(static_cast<double>(lo) + (static_cast<double>(hi) - static_cast<double>(lo)) * unit());
  }
  /// Log-uniform in [lo, hi] (lo > 0).
  template <class T>
  T log_uniform(T lo, T hi) {
    return static_cast<T>(std::exp(uniform<double>(std::log(static_cast<double>(lo)), std::log(static_cast<double>(hi)))));
  }
  /// Standard normal (Box-Muller).
  double normal() {
    const double u1 = 1.0 - unit(), u2 = unit();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::mt19937_64 engine_;
};

/// A tolerance per precision.
template <class T>
constexpr T pick(double for_double, double for_float) {
  return static_cast<T>(sizeof(T) >= sizeof(double) ? for_double : for_float);
}

/// Every coefficient of a multivector type uniform in [lo, hi].
template <class MV>
MV random_mv(Rng& rng, typename MV::value_type lo = -1, typename MV::value_type hi = 1) {
  MV m;
  for (std::size_t i = 0; i < MV::size; ++i) m[i] = rng.uniform(lo, hi);
  return m;
}

template <class T>
Vec3<T> random_vec3(Rng& rng, T lo, T hi) {
  return Vec3<T>(rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi));
}

/// Uniform direction on the unit sphere.
template <class T>
Vec3<T> random_unit(Rng& rng) {
  for (;;) {
    const Eigen::Vector3d v(rng.normal(), rng.normal(), rng.normal());
    const double n = v.norm();
    if (n > 1e-3) return (v / n).cast<T>();
  }
}

/// A random rigid+scale transformation, kept in both representations.
template <class T>
struct Similarity {
  Vec3<T> t;
  Vec3<T> axis;  ///< unit
  T angle;
  T scale;

  [[nodiscard]] Eigen::Quaternion<T> quaternion() const { return Eigen::Quaternion<T>(Eigen::AngleAxis<T>(angle, axis)); }
  [[nodiscard]] Eigen::Matrix<T, 3, 3> linear() const { return scale * Eigen::AngleAxis<T>(angle, axis).toRotationMatrix(); }
  [[nodiscard]] Vec3<T> operator()(const Vec3<T>& x) const { return linear() * x + t; }
  [[nodiscard]] Rotor<T> rotor() const { return cgamesh::cga::rotor(axis, angle); }
  [[nodiscard]] Versor<T> versor() const { return similarity(t, rotor(), scale); }
  [[nodiscard]] Motor<T> motor() const { return Motor<T>(translator(t) * rotor()); }
};

/// Translation in [-10, 10]^3, uniform axis, angle in [0, pi], scale in [0.2, 5] (log-uniform).
template <class T>
Similarity<T> random_similarity(Rng& rng) {
  Similarity<T> s;
  s.t = random_vec3<T>(rng, -10, 10);
  s.axis = random_unit<T>(rng);
  s.angle = rng.uniform<T>(0, std::numbers::pi_v<T>);
  s.scale = rng.log_uniform<T>(T(0.2), T(5));
  return s;
}

/// Widening to the dense type (a copy when it is dense already).
template <class T, BladeMask M>
Dense<T> dense(const Multivector<T, M>& m) {
  return Dense<T>(m);
}

template <class T, BladeMask M>
std::string to_string(const Multivector<T, M>& m) {
  std::ostringstream os;
  os.precision(17);
  bool first = true;
  for (std::size_t i = 0; i < Multivector<T, M>::size; ++i) {
    if (m[i] == T(0)) continue;
    os << (first ? "" : " + ") << m[i] << "*" << blade_name(Multivector<T, M>::blades[i]);
    first = false;
  }
  return first ? "0" : os.str();
}

/// |actual - expected| <= tol * max(1, max_abs(expected)) for every one of the 32 blades.
template <class T, BladeMask A, BladeMask B>
::testing::AssertionResult mv_near(const Multivector<T, A>& actual, const Multivector<T, B>& expected, T tol) {
  const Dense<T> a(actual), e(expected);
  const T bound = tol * std::max(T(1), max_abs(e));
  std::ostringstream bad;
  bad.precision(17);
  bool ok = true;
  for (BladeIndex b = 0; b < kBladeCount; ++b) {
    const T d = std::abs(a[b] - e[b]);
    if (!(d <= bound)) {  // NaN fails
      ok = false;
      bad << "\n  blade " << blade_name(b) << ": actual " << a[b] << ", expected " << e[b] << ", diff " << d;
    }
  }
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "multivectors differ (bound " << bound << "):" << bad.str()
                                       << "\n  actual   = " << to_string(a) << "\n  expected = " << to_string(e);
}

/// |actual - expected|_inf <= tol * max(1, |expected|_inf).
template <class T, int R, int C>
::testing::AssertionResult mat_near(const Eigen::Matrix<T, R, C>& actual, const Eigen::Matrix<T, R, C>& expected,
                                    T tol) {
  const T bound = tol * std::max(T(1), expected.cwiseAbs().maxCoeff());
  const T d = (actual - expected).cwiseAbs().maxCoeff();
  if (d <= bound && actual.allFinite()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "matrices differ by " << d << " (bound " << bound << ")\n  actual   = "
                                       << actual.transpose() << "\n  expected = " << expected.transpose();
}

/// Every coefficient finite.
template <class T, BladeMask M>
::testing::AssertionResult all_finite(const Multivector<T, M>& m) {
  if (is_finite(m)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "non-finite coefficient in " << to_string(m);
}

/// Divides by the coefficient of largest magnitude of `reference` (same blade in both), so
/// that two multiples of the same blade can be compared.
template <class T, BladeMask M, BladeMask N>
std::pair<Dense<T>, Dense<T>> normalise_pair(const Multivector<T, M>& x, const Multivector<T, N>& reference) {
  const Dense<T> a(x), r(reference);
  BladeIndex best = 0;
  for (BladeIndex b = 1; b < kBladeCount; ++b)
    if (std::abs(r[b]) > std::abs(r[best])) best = b;
  return {a / a[best], r / r[best]};
}

/// Down-projection through the sandwich: the point map of a versor.
template <class T, BladeMask M>
Vec3<T> transform_point(const Multivector<T, M>& v, const Vec3<T>& x) {
  return down(sandwich(v, up(x)));
}

}  // namespace cgatest

// Variadic so that template arguments with commas need no extra parentheses.
#define EXPECT_MV_NEAR(...) EXPECT_TRUE(::cgatest::mv_near(__VA_ARGS__))
#define ASSERT_MV_NEAR(...) ASSERT_TRUE(::cgatest::mv_near(__VA_ARGS__))
#define EXPECT_MAT_NEAR(...) EXPECT_TRUE(::cgatest::mat_near(__VA_ARGS__))
