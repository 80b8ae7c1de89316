#include "cgamesh/deform/harmonic_field.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "cgamesh/deform/harmonic_handles.hpp"
#include "cgamesh/errors.hpp"
#include "deform/deform_fixtures.hpp"

namespace {

using namespace cgamesh;              // NOLINT(google-build-using-namespace)
using namespace cgamesh_deform_test;  // NOLINT(google-build-using-namespace)

/// Field with value 0 on `zero` and 1 on `one`.
Eigen::VectorXd two_sided(const mesh::Mesh& m, const std::vector<int>& zero, const std::vector<int>& one,
                          const deform::HarmonicOptions& options = {}) {
  std::vector<int> constrained = zero;
  constrained.insert(constrained.end(), one.begin(), one.end());
  Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(constrained.size()), 1);
  boundary.bottomRows(static_cast<Eigen::Index>(one.size())).setOnes();
  return deform::harmonic_solve(deform::harmonic_precompute(m, constrained, options), boundary).col(0);
}

// Every band of the cylinder is the same, so the discrete harmonic function is exactly linear
// in the ring index, i.e. in z, for either weighting.
TEST(HarmonicField, CylinderFieldIsLinearAlongTheAxis) {
  for (const auto weights : {deform::LaplacianWeights::mean_value, deform::LaplacianWeights::cotangent}) {
    const mesh::Mesh m = cylinder(24, 11);
    const Eigen::VectorXd f = two_sided(m, slab(m, 2, 0.0, false), slab(m, 2, 0.0, true), {weights});
    for (Eigen::Index i = 0; i < m.vertex_count(); ++i) EXPECT_NEAR(f[i], m.positions(i, 2), 1e-6) << i;
  }
}

// Seam copies are one unknown: constraining one copy constrains the other, and the field does
// not tear along the seam.
TEST(HarmonicField, WeldsVerticesAtTheSamePosition) {
  const mesh::Mesh m = cylinder(16, 9, true);
  std::vector<int> bottom, top;
  for (int c = 0; c < 16; ++c) bottom.push_back(c), top.push_back(8 * 17 + c);  // seam copy (column 16) left out
  const Eigen::VectorXd f = two_sided(m, bottom, top);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) EXPECT_NEAR(f[i], m.positions(i, 2), 1e-6) << i;
  EXPECT_EQ(f[16], 0.0);
  EXPECT_EQ(f[8 * 17 + 16], 1.0);
}

TEST(HarmonicField, HoldsBoundaryValuesExactlyAndStaysInRange) {
  const mesh::Mesh m = asset_mesh("spot.obj");
  const std::vector<int> zero = slab(m, 1, 0.1, false), one = slab(m, 1, 0.1, true);
  const Eigen::VectorXd f = two_sided(m, zero, one);
  for (const int v : zero) EXPECT_EQ(f[v], 0.0);
  for (const int v : one) EXPECT_EQ(f[v], 1.0);
  EXPECT_GE(f.minCoeff(), 0.0);
  EXPECT_LE(f.maxCoeff(), 1.0);
  // Harmonic, so not trivially constant: the middle of the mesh is strictly between.
  EXPECT_GT(f.maxCoeff() - f.minCoeff(), 0.99);
}

TEST(HarmonicField, SolvesManyRightHandSidesAtOnce) {
  const mesh::Mesh m = cylinder(12, 7);
  const std::vector<int> bottom = slab(m, 2, 0.0, false), top = slab(m, 2, 0.0, true);
  std::vector<int> constrained = bottom;
  constrained.insert(constrained.end(), top.begin(), top.end());
  const auto pre = deform::harmonic_precompute(m, constrained);
  Eigen::MatrixXd boundary(static_cast<Eigen::Index>(constrained.size()), 2);
  boundary.col(0).setLinSpaced(-1, 1);
  boundary.col(1).setConstant(3.5);
  const Eigen::MatrixXd f = deform::harmonic_solve(pre, boundary);
  ASSERT_EQ(f.rows(), m.vertex_count());
  ASSERT_EQ(f.cols(), 2);
  EXPECT_NEAR((f.col(1).array() - 3.5).abs().maxCoeff(), 0.0, 1e-9);  // constants are harmonic
  EXPECT_GE(f.col(0).minCoeff(), -1.0);
  EXPECT_LE(f.col(0).maxCoeff(), 1.0);
}

TEST(HarmonicField, RejectsBadConstraints) {
  const mesh::Mesh m = cylinder(8, 4);
  EXPECT_THROW((void)deform::harmonic_precompute(m, std::vector<int>{}), InvalidInputError);
  EXPECT_THROW((void)deform::harmonic_precompute(m, std::vector<int>{0, 32}), InvalidInputError);
  EXPECT_THROW((void)deform::harmonic_precompute(m, std::vector<int>{-1}), InvalidInputError);
  const auto pre = deform::harmonic_precompute(m, std::vector<int>{0, 1});
  EXPECT_THROW((void)deform::harmonic_solve(pre, Eigen::MatrixXd::Zero(3, 1)), InvalidInputError);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Zero(2, 1);
  nan(1, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)deform::harmonic_solve(pre, nan), InvalidInputError);
}

TEST(HarmonicField, RejectsAPartWithoutConstraint) {
  // Two cylinders side by side; only the first is constrained.
  const mesh::Mesh a = cylinder(8, 4);
  mesh::Mesh two = a;
  two.positions.resize(2 * a.vertex_count(), 3);
  two.positions << a.positions, (a.positions.rowwise() + Eigen::RowVector3f(5, 0, 0));
  two.faces.resize(2 * a.face_count(), 3);
  two.faces << a.faces, (a.faces.array() + static_cast<int>(a.vertex_count())).matrix();
  try {
    (void)deform::harmonic_precompute(two, std::vector<int>{0, 31});
    FAIL() << "expected InvalidInputError";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("no constrained vertex"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW((void)deform::harmonic_precompute(two, std::vector<int>{0, 32}));
}

// Section IV: the coordinates of every vertex sum to 1 and are non-negative.
TEST(HarmonicCoordinates, PartitionOfUnityAndNonNegativeOnRealMeshes) {
  for (const char* name : {"cow.obj", "woody.obj", "alligator.obj", "spot.obj"}) {
    SCOPED_TRACE(name);
    const mesh::Mesh m = asset_mesh(name);
    const std::vector<std::vector<int>> handles{slab(m, 0, 0.05, false), slab(m, 0, 0.05, true),
                                                slab(m, 1, 0.05, true)};
    const Eigen::MatrixXd c = deform::harmonic_coordinates(m, handles);
    ASSERT_EQ(c.rows(), m.vertex_count());
    ASSERT_EQ(c.cols(), 3);
    EXPECT_LT((c.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-9);
    EXPECT_GE(c.minCoeff(), -1e-12);
    EXPECT_LE(c.maxCoeff(), 1.0 + 1e-12);
    for (std::size_t j = 0; j < handles.size(); ++j)
      for (const int v : handles[j]) EXPECT_EQ(c(v, static_cast<Eigen::Index>(j)), 1.0);
  }
}

TEST(HarmonicCoordinates, RejectsOverlappingOrEmptyHandles) {
  const mesh::Mesh m = cylinder(8, 4);
  EXPECT_THROW((void)deform::harmonic_coordinates(m, std::vector<std::vector<int>>{{0, 1}, {1, 2}}), InvalidInputError);
  EXPECT_THROW((void)deform::harmonic_coordinates(m, std::vector<std::vector<int>>{{0}, {}}), InvalidInputError);
  EXPECT_THROW((void)deform::harmonic_coordinates(m, std::vector<std::vector<int>>{}), InvalidInputError);
}

}  // namespace
