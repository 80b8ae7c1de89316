#include "cgamesh/deform/bspline_fit.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "cga/test_util.hpp"
#include "cgamesh/deform/spline_deform.hpp"
#include "cgamesh/errors.hpp"

namespace {

using namespace cgamesh;  // NOLINT(google-build-using-namespace)
using cga::Versor;
using Generator = cga::SimilarityGenerator<double>;

Generator random_generator(cgatest::Rng& rng, bool dilate) {
  Generator g;
  for (std::size_t k = 0; k < 6; ++k) g[k] = rng.uniform(-0.6, 0.6);
  if (dilate) g[6] = rng.uniform(-0.3, 0.3);
  return g;
}

/// Keys on the B-spline with the given control generators, at `count` uniform parameters.
std::vector<Versor<double>> keys_on_spline(const std::vector<Generator>& control, int count,
                                           std::vector<double>& parameters) {
  std::vector<Versor<double>> keys;
  std::vector<double> w(control.size());
  for (int i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) / (count - 1);
    parameters.push_back(t);
    deform::spline_weights({deform::SplineBasis::bspline, 3, {}}, t, w);
    Generator sum;
    for (std::size_t j = 0; j < control.size(); ++j) sum += control[j] * w[j];
    keys.push_back(cga::exp(sum));
  }
  return keys;
}

// Eq. (3): keys that lie on a cubic B-spline give back its control motors, residual 0.
TEST(DeformBsplineFit, ExactOnKeysThatLieOnASpline) {
  cgatest::Rng rng(11);
  for (const bool dilate : {false, true}) {
    std::vector<Generator> control;
    for (int j = 0; j < 6; ++j) control.push_back(random_generator(rng, dilate));
    std::vector<double> parameters;
    const auto keys = keys_on_spline(control, 20, parameters);
    const deform::BsplineFit fit = deform::fit_bspline_motors(keys, parameters, 6);
    EXPECT_FALSE(fit.used_svd);
    EXPECT_LT(fit.max_residual, 1e-10);
    ASSERT_EQ(fit.control.size(), 6u);
    for (std::size_t j = 0; j < 6; ++j) {
      const Generator g = cga::log(fit.control[j]);
      for (std::size_t k = 0; k < Generator::size; ++k) EXPECT_NEAR(g[k], control[j][k], 1e-9) << j << " " << k;
    }
  }
}

TEST(DeformBsplineFit, ReportsTheResidualOfKeysOffTheSpline) {
  cgatest::Rng rng(12);
  std::vector<Versor<double>> keys;
  std::vector<double> parameters;
  for (int i = 0; i < 15; ++i) {
    keys.push_back(cga::exp(random_generator(rng, false)));
    parameters.push_back(i / 14.0);
  }
  const deform::BsplineFit fit = deform::fit_bspline_motors(keys, parameters, 5);
  EXPECT_GT(fit.rms_residual, 1e-3);
  EXPECT_LE(fit.rms_residual, fit.max_residual);
  // The reported residual is that of the returned control motors.
  double sum = 0;
  std::vector<double> w(5);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    deform::spline_weights({deform::SplineBasis::bspline, 3, {}}, parameters[i], w);
    Generator s;
    for (std::size_t j = 0; j < 5; ++j) s += cga::log(fit.control[j]) * w[j];
    const Generator d = s - cga::log(keys[i]);
    for (std::size_t k = 0; k < Generator::size; ++k) sum += d[k] * d[k];
  }
  EXPECT_NEAR(std::sqrt(sum / 15.0), fit.rms_residual, 1e-9);
}

// All keys at one parameter: A^T A is singular, the SVD gives a finite least-squares answer.
TEST(DeformBsplineFit, FallsBackToSvdWhenIllConditioned) {
  cgatest::Rng rng(13);
  std::vector<Versor<double>> keys;
  for (int i = 0; i < 6; ++i) keys.push_back(cga::exp(random_generator(rng, false)));
  const std::vector<double> parameters(6, 0.0);
  const deform::BsplineFit fit = deform::fit_bspline_motors(keys, parameters, 5);
  EXPECT_TRUE(fit.used_svd);
  for (const auto& c : fit.control)
    for (std::size_t k = 0; k < Versor<double>::size; ++k) EXPECT_TRUE(std::isfinite(c[k]));
  EXPECT_TRUE(std::isfinite(fit.rms_residual));
}

TEST(DeformBsplineFit, RejectsBadArguments) {
  const std::vector<Versor<double>> keys(4, Versor<double>(cga::basis_blade<double, cga::blade::scalar>()));
  EXPECT_THROW((void)deform::fit_bspline_motors(keys, std::vector<double>{0, 1}, 4), InvalidInputError);
  EXPECT_THROW((void)deform::fit_bspline_motors(keys, std::vector<double>{0, 0.2, 0.4, 1}, 3), InvalidInputError);
  EXPECT_THROW((void)deform::fit_bspline_motors(keys, std::vector<double>{0, 0.2, NAN, 1}, 4), InvalidInputError);
}

}  // namespace
