// The Newton polar decomposition against Eigen's SVD-based computeRotationScaling.
#include "anim/polar.hpp"

#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace {

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

/// r s as the SVD gives it, and both factors' properties.
void expect_matches_svd(const Eigen::Matrix3d& l, const char* what, int k) {
  Eigen::Matrix3d r, s, r_svd, s_svd;
  cgamesh::detail::rotation_scaling(l, r, s);
  Eigen::Affine3d a = Eigen::Affine3d::Identity();
  a.linear() = l;
  a.computeRotationScaling(&r_svd, &s_svd);
  const double scale = l.cwiseAbs().maxCoeff();
  EXPECT_LE((r - r_svd).cwiseAbs().maxCoeff(), 1e-12) << what << " " << k;
  EXPECT_LE((s - s_svd).cwiseAbs().maxCoeff(), 1e-12 * scale) << what << " " << k;
  EXPECT_LE((r * s - l).cwiseAbs().maxCoeff(), 1e-12 * scale) << what << " " << k;
  EXPECT_LE((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-13) << what << " " << k;
  EXPECT_NEAR(r.determinant(), 1.0, 1e-13) << what << " " << k;
}

TEST(Polar, NewtonEqualsTheSvdOnRotationsScalesAndShears) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1, 1), log_scale(-4.6, 4.6);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Matrix3d q = random_rotation(rng);
    // A float rig's near-rotation: a few 1e-7 off.
    Eigen::Matrix3d noise;
    noise << u(rng), u(rng), u(rng), u(rng), u(rng), u(rng), u(rng), u(rng), u(rng);
    expect_matches_svd(q + 3e-7 * noise, "near rotation", k);
    // Uniform scale from 0.01 to 100, non-uniform scale, and shear.
    expect_matches_svd(std::exp(log_scale(rng)) * q, "uniform scale", k);
    const Eigen::Vector3d d(std::exp(log_scale(rng)), std::exp(log_scale(rng)), std::exp(log_scale(rng)));
    expect_matches_svd(q * d.asDiagonal() * random_rotation(rng), "scale", k);
    Eigen::Matrix3d shear = Eigen::Matrix3d::Identity();
    shear(0, 1) = 2 * u(rng);
    shear(1, 2) = 2 * u(rng);
    expect_matches_svd(q * shear, "shear", k);
    // Mirrors and singular matrices take the SVD itself.
    expect_matches_svd(q * Eigen::Vector3d(1, 1, -1).asDiagonal() * d.asDiagonal(), "mirror", k);
  }
  expect_matches_svd(Eigen::Matrix3d::Zero(), "zero", 0);
  expect_matches_svd(Eigen::Vector3d(1, 2, 0).asDiagonal() * random_rotation(rng), "singular", 0);
}

}  // namespace
