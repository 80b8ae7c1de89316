#include "cgamesh/deform/motor_blend.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/deform/harmonic_handles.hpp"
#include "cgamesh/deform/spline_deform.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/subdivide.hpp"

#include "cga/test_util.hpp"
#include "deform/deform_fixtures.hpp"

namespace {

using namespace cgamesh;              // NOLINT(google-build-using-namespace)
using namespace cgamesh_deform_test;  // NOLINT(google-build-using-namespace)
using cga::Versor;
using Vec3 = Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

Versor<double> identity() { return Versor<double>(cga::basis_blade<double, cga::blade::scalar>()); }
Versor<double> rigid(const Vec3& t, const Vec3& axis, double angle) {
  return cga::similarity(t, cga::rotor(axis, angle), 1.0);
}

/// Largest distance between the rows of a and of the rest positions mapped by `v`.
double distance_to_mapped(const mesh::RowMatrixXf<3>& a, const mesh::RowMatrixXf<3>& rest, const Versor<double>& v) {
  const cga::PointMap<double> map(v);
  double worst = 0;
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    const Vec3 expected = map(rest.row(i).transpose().cast<double>());
    worst = std::max(worst, (a.row(i).transpose().cast<double>() - expected).norm());
  }
  return worst;
}

TEST(DeformMotorBlend, AffineOfExpMatchesTheVersor) {
  cgatest::Rng rng(5);
  std::vector<cga::SimilarityGenerator<double>> cases;
  const auto gen = [](std::array<double, 7> c) {
    cga::SimilarityGenerator<double> g;
    for (std::size_t k = 0; k < 7; ++k) g[k] = c[k];
    return g;
  };
  cases.push_back(gen({0, 0, 0, 0, 0, 0, 0}));
  cases.push_back(gen({0, 0, 0, 0.3, -1, 2, 0}));               // pure translation
  cases.push_back(gen({kPi / 2, 0, 0, 0.3, -1, 2, 0}));         // 180 degree screw
  cases.push_back(gen({1e-7, 2e-7, 0, 1, 1, 1, 0}));            // almost a translation
  cases.push_back(gen({0, 0, 0, 0, 0, 0, -0.4}));               // pure dilation
  cases.push_back(gen({0.2, -0.1, 0.5, 0.3, 0.1, -0.2, 0.3}));  // everything
  for (int k = 0; k < 50; ++k) {
    std::array<double, 7> c{};
    for (double& x : c) x = rng.uniform(-1.5, 1.5);
    if (k % 2 == 0) c[6] = 0;
    cases.push_back(gen(c));
  }
  for (const auto& b : cases) {
    const Eigen::Matrix<double, 3, 4> fast = deform::similarity_exp_affine(b);
    const cga::PointMap<double> reference(cga::exp(b));
    ASSERT_TRUE(reference.is_affine());
    EXPECT_LT((fast - reference.affine_matrix()).cwiseAbs().maxCoeff(), 1e-12) << fast << "\n\n"
                                                                               << reference.affine_matrix();
  }
}

TEST(DeformSpline, BasesArePartitionsOfUnityThatInterpolateTheEnds) {
  using deform::SplineBasis;
  const std::vector<std::pair<deform::SplineOptions, std::size_t>> bases{{{SplineBasis::linear, 3, {}}, 2},
                                                                         {{SplineBasis::linear, 3, {}}, 5},
                                                                         {{SplineBasis::quadratic_lagrange, 3, {}}, 3},
                                                                         {{SplineBasis::bezier, 3, {}}, 4},
                                                                         {{SplineBasis::bspline, 3, {}}, 4},
                                                                         {{SplineBasis::bspline, 3, {}}, 7},
                                                                         {{SplineBasis::bspline, 2, {}}, 5},
                                                                         {{SplineBasis::bspline, 1, {}}, 3}};
  for (const auto& [options, n] : bases) {
    std::vector<double> w(n);
    for (int k = 0; k <= 40; ++k) {
      deform::spline_weights(options, k / 40.0, w);
      double sum = 0;
      for (const double x : w) sum += x;
      EXPECT_NEAR(sum, 1.0, 1e-12);
    }
    deform::spline_weights(options, 0.0, w);
    EXPECT_EQ(w.front(), 1.0);
    deform::spline_weights(options, 1.0, w);
    EXPECT_EQ(w.back(), 1.0);
  }
  // Clamped cubic B-spline on 4 control points is the cubic Bezier.
  std::vector<double> a(4), b(4);
  for (int k = 0; k <= 10; ++k) {
    deform::spline_weights({SplineBasis::bspline, 3, {}}, k / 10.0, a);
    deform::spline_weights({SplineBasis::bezier, 3, {}}, k / 10.0, b);
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(a[j], b[j], 1e-12);
  }
  std::vector<double> three(3);
  EXPECT_THROW(deform::spline_weights({SplineBasis::bspline, 3, {}}, 0.5, three), InvalidInputError);
  EXPECT_THROW(deform::spline_weights({SplineBasis::quadratic_lagrange, 3, {}}, 0.5, a), InvalidInputError);
}

// Section III.B: the quadratic path S(lambda) passes through R1, R2, R3 at 0, 1/2, 1.
TEST(DeformSpline, QuadraticLagrangePathPassesThroughItsKeys) {
  const std::vector<Versor<double>> keys{rigid(Vec3(0, 0, 0), Vec3(0, 0, 1), 0.3),
                                         rigid(Vec3(1, 2, 0), Vec3(1, 0, 0), kPi),
                                         cga::similarity(Vec3(0, 0, 3), cga::rotor(Vec3(0, 1, 1), 2.0), 1.5)};
  std::vector<double> w(3);
  for (int j = 0; j < 3; ++j) {
    deform::spline_weights({deform::SplineBasis::quadratic_lagrange, 3, {}}, j / 2.0, w);
    const Versor<double> s = cga::blend(std::span<const Versor<double>>(keys), std::span<const double>(w));
    const cga::PointMap<double> a(s), b(keys[static_cast<std::size_t>(j)]);
    EXPECT_LT((a.affine_matrix() - b.affine_matrix()).cwiseAbs().maxCoeff(), 1e-12) << j;
  }
}

TEST(DeformSpline, IdentityKeysLeaveTheMeshUnchanged) {
  const mesh::Mesh m = asset_mesh("spot.obj");
  const std::vector<int> start = slab(m, 1, 0.1, false), end = slab(m, 1, 0.1, true);
  // Rest keys away from the identity: binding must undo them.
  const std::vector<Versor<double>> rest{rigid(Vec3(0.1, 0, 0), Vec3(0, 1, 0), 0.5), identity(),
                                         cga::similarity(Vec3(0, 0, 1), cga::rotor(Vec3(1, 1, 0), -1.0), 2.0),
                                         identity()};
  const deform::MotorBlend bound = deform::bind_spline(m, start, end, rest);
  mesh::RowMatrixXf<3> out;
  bound.deform(rest, out);
  EXPECT_LE((out - m.positions).cwiseAbs().maxCoeff(), 1e-6 * diagonal(m));
  const deform::MotorBlend plain = deform::bind_spline(m, start, end, std::vector<Versor<double>>(4, identity()));
  plain.deform(std::vector<Versor<double>>(4, identity()), out);
  EXPECT_LE((out - m.positions).cwiseAbs().maxCoeff(), 1e-6 * diagonal(m));
}

TEST(DeformSpline, EqualKeysMoveTheWholeMeshRigidly) {
  const mesh::Mesh m = asset_mesh("spot.obj");
  const Versor<double> motion = rigid(Vec3(0.5, -1, 2), Vec3(1, 2, 3), 2.5);
  for (const auto basis : {deform::SplineBasis::linear, deform::SplineBasis::quadratic_lagrange,
                           deform::SplineBasis::bezier, deform::SplineBasis::bspline}) {
    const std::size_t n = basis == deform::SplineBasis::linear               ? 2
                          : basis == deform::SplineBasis::quadratic_lagrange ? 3
                                                                             : 5;
    const deform::MotorBlend bound = deform::bind_spline(m, slab(m, 2, 0.1, false), slab(m, 2, 0.1, true),
                                                         std::vector<Versor<double>>(n, identity()), {basis, 3, {}});
    mesh::RowMatrixXf<3> out;
    bound.deform(std::vector<Versor<double>>(n, motion), out);
    EXPECT_LE(distance_to_mapped(out, m.positions, motion), 2e-6 * diagonal(m)) << static_cast<int>(basis);
  }
}

TEST(DeformSpline, QuantisedParameterDeformsAsTheExactOne) {
  // Above 16384 levels: 47k vertices.
  const mesh::Mesh m = mesh::subdivide_midpoint(mesh::subdivide_midpoint(asset_mesh("spot.obj")));
  const std::vector<int> start = slab(m, 1, 0.1, false), end = slab(m, 1, 0.1, true);
  const std::vector<Versor<double>> rest(4, identity());
  const std::vector<Versor<double>> keys{identity(), rigid(Vec3(0, 0.1, 0), Vec3(0, 0, 1), 0.6),
                                         rigid(Vec3(0.2, 0, 0), Vec3(1, 0, 0), -0.9),
                                         cga::similarity(Vec3(0, 0, 0.3), cga::rotor(Vec3(0, 1, 0), 1.2), 1.5)};
  deform::SplineOptions exact;
  exact.levels = 0;
  ASSERT_GT(m.vertex_count(), deform::SplineOptions{}.levels);
  mesh::RowMatrixXf<3> a, b;
  deform::bind_spline(m, start, end, rest).deform(keys, a);
  deform::bind_spline(m, start, end, rest, exact).deform(keys, b);
  const double worst = (a - b).rowwise().norm().maxCoeff();
  EXPECT_LE(worst, 1e-3 * diagonal(m)) << "rounding lambda to 1/16383 moves a vertex this far";
  EXPECT_GT(worst, 0.0) << "the quantised path was not taken";
  for (const int v : start) EXPECT_LE((a.row(v) - b.row(v)).norm(), 1e-6 * diagonal(m)) << "lambda = 0 is a level";
  for (const int v : end) EXPECT_LE((a.row(v) - b.row(v)).norm(), 1e-6 * diagonal(m)) << "lambda = 1 is a level";
  deform::SplineOptions bad;
  bad.levels = 1;
  EXPECT_THROW((void)deform::bind_spline(m, start, end, rest, bad), InvalidInputError);
  EXPECT_THROW(deform::MotorBlend(m.positions, deform::WeightMatrix::Ones(2, 1), std::vector<int>(m.vertex_count(), 2),
                                  std::vector<Versor<double>>(1, identity())),
               InvalidInputError);
}

TEST(DeformSpline, EndHandlesFollowTheirKeysRigidly) {
  const mesh::Mesh m = asset_mesh("spot.obj");
  const std::vector<int> start = slab(m, 1, 0.1, false), end = slab(m, 1, 0.1, true);
  const std::vector<Versor<double>> rest(3, identity());
  const deform::MotorBlend bound =
      deform::bind_spline(m, start, end, rest, {deform::SplineBasis::quadratic_lagrange, 3, {}});
  const std::vector<Versor<double>> keys{rigid(Vec3(0, 0.2, 0), Vec3(0, 0, 1), 0.2), identity(),
                                         rigid(Vec3(0.3, 0, 0), Vec3(1, 0, 0), -0.7)};
  mesh::RowMatrixXf<3> out;
  bound.deform(keys, out);
  const cga::PointMap<double> first(keys[0]), last(keys[2]);
  for (const int v : start)
    EXPECT_LT((out.row(v).transpose().cast<double>() - first(m.positions.row(v).transpose().cast<double>())).norm(),
              1e-5);
  for (const int v : end)
    EXPECT_LT((out.row(v).transpose().cast<double>() - last(m.positions.row(v).transpose().cast<double>())).norm(),
              1e-5);
}

TEST(DeformSpline, TranslatorsAndHalfTurnsBlendWithoutNaN) {
  const mesh::Mesh m = cylinder(16, 12);
  const std::vector<Versor<double>> keys{cga::translator(Vec3(0, 0, 2)), rigid(Vec3(0, 0, 0), Vec3(1, 0, 0), kPi),
                                         identity(), rigid(Vec3(1, 1, 0), Vec3(0, 1, 0), kPi),
                                         cga::translator(Vec3(-3, 0, 0))};
  const deform::MotorBlend bound =
      deform::bind_spline(m, slab(m, 2, 0.0, false), slab(m, 2, 0.0, true), std::vector<Versor<double>>(5, identity()));
  mesh::RowMatrixXf<3> out;
  bound.deform(keys, out);
  EXPECT_TRUE(out.allFinite());
  std::vector<double> w(2);
  for (int k = 0; k <= 100; ++k) {
    w = {1 - k / 100.0, k / 100.0};
    const std::vector<Versor<double>> pair{keys[1], keys[3]};
    const auto v = cga::blend(std::span<const Versor<double>>(pair), std::span<const double>(w));
    EXPECT_TRUE(cga::PointMap<double>(v).affine_matrix().allFinite()) << k;
    EXPECT_TRUE(deform::similarity_exp_affine(cga::log(pair[0]) * w[0] + cga::log(pair[1]) * w[1]).allFinite());
  }
}

// Dilating keys: the blended scale is the weighted geometric mean of the key scales, so
// between D(1) and D(4) a vertex at parameter lambda scales by 4^lambda about the origin.
TEST(DeformSpline, DilatingKeysScaleByTheBlendedFactor) {
  const mesh::Mesh m = cylinder(16, 12);
  const deform::MotorBlend bound =
      deform::bind_spline(m, slab(m, 2, 0.0, false), slab(m, 2, 0.0, true), std::vector<Versor<double>>(2, identity()),
                          {deform::SplineBasis::linear, 3, {}});
  const std::vector<Versor<double>> keys{identity(), Versor<double>(cga::dilator(4.0))};
  mesh::RowMatrixXf<3> out;
  bound.deform(keys, out);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const double lambda = bound.weight(i, 1);
    EXPECT_NEAR(lambda, m.positions(i, 2), 1e-6);
    const Eigen::Vector3d expected = std::pow(4.0, lambda) * m.positions.row(i).transpose().cast<double>();
    EXPECT_LT((out.row(i).transpose().cast<double>() - expected).norm(), 1e-5) << i;
  }
  // Equal dilating keys move everything by that similarity, dilation included.
  const Versor<double> trs = cga::similarity(Vec3(1, 0, -1), cga::rotor(Vec3(0, 1, 0), 0.8), 2.5);
  bound.deform(std::vector<Versor<double>>(2, trs), out);
  EXPECT_LE(distance_to_mapped(out, m.positions, trs), 1e-5);
}

TEST(DeformHarmonicHandles, EqualKeysMoveTheMeshAndIdentityKeepsIt) {
  const mesh::Mesh m = asset_mesh("cow.obj");
  const std::vector<std::vector<int>> handles{slab(m, 0, 0.05, false), slab(m, 0, 0.05, true), slab(m, 1, 0.05, true)};
  const std::vector<Versor<double>> rest(3, identity());
  const deform::MotorBlend bound = deform::bind_harmonic_handles(m, handles, rest);
  mesh::RowMatrixXf<3> out;
  bound.deform(rest, out);
  EXPECT_LE((out - m.positions).cwiseAbs().maxCoeff(), 1e-6 * diagonal(m));
  const Versor<double> motion = rigid(Vec3(-1, 0.5, 0.25), Vec3(0, 1, 1), kPi);
  bound.deform(std::vector<Versor<double>>(3, motion), out);
  EXPECT_LE(distance_to_mapped(out, m.positions, motion), 2e-6 * diagonal(m));
  // Each handle follows its own key rigidly.
  const std::vector<Versor<double>> keys{identity(), rigid(Vec3(0, 0.3, 0), Vec3(0, 0, 1), 0.4),
                                         rigid(Vec3(0.1, 0, 0), Vec3(1, 0, 0), -0.3)};
  bound.deform(keys, out);
  for (std::size_t j = 0; j < 3; ++j) {
    mesh::RowMatrixXf<3> sub(static_cast<Eigen::Index>(handles[j].size()), 3), ref = sub;
    for (std::size_t k = 0; k < handles[j].size(); ++k) {
      sub.row(static_cast<Eigen::Index>(k)) = out.row(handles[j][k]);
      ref.row(static_cast<Eigen::Index>(k)) = m.positions.row(handles[j][k]);
    }
    EXPECT_LE(distance_to_mapped(sub, ref, keys[j]), 1e-5) << j;
  }
}

TEST(DeformMotorBlend, ThreadCountDoesNotChangeTheResult) {
  const mesh::Mesh m = mesh::subdivide_midpoint(asset_mesh("cow.obj"));  // enough vertices for 2+ jobs
  const std::vector<std::vector<int>> handles{slab(m, 0, 0.05, false), slab(m, 0, 0.05, true)};
  const std::vector<Versor<double>> rest(2, identity());
  const std::vector<Versor<double>> keys{identity(), rigid(Vec3(0, 0.3, 0), Vec3(0, 0, 1), 1.4)};
  mesh::RowMatrixXf<3> one, many;
  deform::bind_harmonic_handles(m, handles, rest, {}, {1}).deform(keys, one);
  deform::bind_harmonic_handles(m, handles, rest, {}, {3}).deform(keys, many);
  EXPECT_EQ(one, many);
}

TEST(DeformMotorBlend, RejectsMismatchedSizes) {
  const mesh::Mesh m = cylinder(8, 4);
  const std::vector<Versor<double>> two(2, identity());
  EXPECT_THROW(deform::MotorBlend(m.positions, deform::WeightMatrix::Zero(3, 2), two), InvalidInputError);
  EXPECT_THROW(deform::MotorBlend(m.positions, deform::WeightMatrix::Zero(32, 2), std::vector<Versor<double>>{}),
               InvalidInputError);
  const deform::MotorBlend b(m.positions, deform::WeightMatrix::Zero(32, 2), two);
  mesh::RowMatrixXf<3> out;
  EXPECT_THROW(b.deform(std::vector<Versor<double>>(3, identity()), out), InvalidInputError);
  EXPECT_THROW(deform::bind_harmonic_handles(m, std::vector<std::vector<int>>{{0}, {31}},
                                             std::vector<Versor<double>>(3, identity())),
               InvalidInputError);
}

}  // namespace
