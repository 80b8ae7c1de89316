// Geometric objects (paper sections 2.1, 2.3): up/down projection, spheres, planes, lines,
// circles, point pairs, distances, and their transformation by versors against Eigen.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)

template <class T>
class Geometry : public ::testing::Test {};
using FloatTypes = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Geometry, FloatTypes);

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------- up / down

TYPED_TEST(Geometry, UpIsTheNullPointOfEq3) {
  using T = TypeParam;
  const Vec3<T> x(1, -2, 3);
  const Vector<T> p = up(x);
  EXPECT_MV_NEAR(p, make_vector<T>(1, -2, 3, 7, 1), T(0));
  EXPECT_EQ(scalar_product(p, p), T(0));                   // null
  EXPECT_EQ(scalar_product(p, einf<T>()), T(-1));         // normalised: X . einf = -1
  EXPECT_MV_NEAR(up(Vec3<T>(Vec3<T>::Zero())), eo<T>(), T(0));  // the origin is eo
  // X . Y = -|x - y|^2 / 2.
  const Vec3<T> y(0.5, 4, -1);
  EXPECT_NEAR(scalar_product(up(x), up(y)), -(x - y).squaredNorm() / 2, pick<T>(1e-14, 1e-5));
}

TYPED_TEST(Geometry, DownInvertsUp) {
  using T = TypeParam;
  Rng rng(101 + sizeof(T));
  const T tol = pick<T>(1e-14, 1e-6);
  for (int k = 0; k < 2000; ++k) {
    const T range = (k % 2 == 0) ? T(1) : T(1000);
    const Vec3<T> x = random_vec3<T>(rng, -range, range);
    EXPECT_MAT_NEAR(down(up(x)), x, T(0));
    // Any non-zero multiple of the point is the same point.
    const T w = (k % 3 == 0 ? T(-1) : T(1)) * rng.log_uniform<T>(T(1e-3), T(1e3));
    EXPECT_MAT_NEAR(down(Vector<T>(up(x) * w)), x, tol);
  }
}

TYPED_TEST(Geometry, DownRejectsNonPoints) {
  using T = TypeParam;
  EXPECT_THROW((void)down(plane<T>(Vec3<T>(0, 0, 1), T(2))), cgamesh::InvalidInputError);
  EXPECT_THROW((void)down(einf<T>()), cgamesh::InvalidInputError);
  EXPECT_THROW((void)down(sphere<T>(Vec3<T>(1, 2, 3), T(1))), cgamesh::InvalidInputError);
  EXPECT_THROW((void)down(sphere<T>(Vec3<T>(0, 0, 0), T(1))), cgamesh::InvalidInputError);
  // An imaginary sphere (negative r^2).
  EXPECT_THROW((void)down(Vector<T>(up(Vec3<T>(1, 0, 0)) + einf<T>() * T(0.5))), cgamesh::InvalidInputError);
  EXPECT_THROW((void)down(make_vector<T>(T(kNaN), 0, 0, 0, 1)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)down(make_vector<T>(0, 0, 0, 0, T(kNaN))), cgamesh::InvalidInputError);
  EXPECT_THROW((void)down(make_vector<T>(0, 0, 0, std::numeric_limits<T>::infinity(), 1)),
               cgamesh::InvalidInputError);
  EXPECT_THROW((void)down(Vector<T>()), cgamesh::InvalidInputError);
  EXPECT_NO_THROW((void)down(eo<T>()));
}

// ---------------------------------------------------------------- spheres and planes

TYPED_TEST(Geometry, SphereAndPlaneParameters) {
  using T = TypeParam;
  const T tol = pick<T>(1e-14, 1e-6);
  const Vector<T> s = sphere<T>(Vec3<T>(1, 2, -3), T(2.5));
  const auto sp = sphere_parameters(s);
  EXPECT_MAT_NEAR(sp.center, Vec3<T>(1, 2, -3), tol);
  EXPECT_NEAR(sp.radius, T(2.5), tol);
  // Any multiple (also negative) is the same sphere; a point is a sphere of radius 0.
  const auto sp2 = sphere_parameters(Vector<T>(s * T(-3)));
  EXPECT_MAT_NEAR(sp2.center, Vec3<T>(1, 2, -3), tol);
  EXPECT_NEAR(sp2.radius, T(2.5), tol * 4);
  EXPECT_EQ(sphere_parameters(up(Vec3<T>(4, 5, 6))).radius, T(0));
  // Points on the sphere satisfy X . S = 0, inside > 0, outside < 0.
  EXPECT_NEAR(scalar_product(up(Vec3<T>(1, 2, -0.5)), s), T(0), tol * 10);
  EXPECT_GT(scalar_product(up(Vec3<T>(1, 2, -3)), s), T(0));
  EXPECT_LT(scalar_product(up(Vec3<T>(10, 2, -3)), s), T(0));
  EXPECT_THROW((void)sphere_parameters(plane<T>(Vec3<T>(1, 0, 0), T(1))), cgamesh::InvalidInputError);
  EXPECT_THROW((void)sphere_parameters(Vector<T>(up(Vec3<T>(0, 0, 0)) + einf<T>())), cgamesh::InvalidInputError);

  // plane(n, d) normalises n: n . x = d.
  const Vector<T> p = plane<T>(Vec3<T>(0, 3, 4), T(10));
  EXPECT_MV_NEAR(p, make_vector<T>(0, T(0.6), T(0.8), 2, 0), tol);
  const auto [n, d] = plane_parameters(p);
  EXPECT_MAT_NEAR(n, Vec3<T>(0, T(0.6), T(0.8)), tol);
  EXPECT_NEAR(d, T(2), tol);
  const auto [n2, d2] = plane_parameters(Vector<T>(p * T(7)));
  EXPECT_MAT_NEAR(n2, n, tol);
  EXPECT_NEAR(d2, d, tol * 4);
  EXPECT_THROW((void)plane_parameters(s), cgamesh::InvalidInputError);
  EXPECT_THROW((void)plane_parameters(einf<T>()), cgamesh::InvalidInputError);
}

TYPED_TEST(Geometry, SignedDistanceIsNDotXMinusD) {
  using T = TypeParam;
  Rng rng(202 + sizeof(T));
  for (int k = 0; k < 1000; ++k) {
    const Vec3<T> n = random_vec3<T>(rng, -3, 3);
    if (n.norm() < T(0.1)) continue;
    const T d = rng.uniform<T>(-5, 5);
    const Vector<T> p = plane(n, d);
    const Vec3<T> x = random_vec3<T>(rng, -10, 10);
    const T expected = (n.dot(x) - d) / n.norm();
    EXPECT_NEAR(signed_distance(x, p), expected, pick<T>(1e-12, 1e-4));
    // The plane vector scaled by a positive factor keeps the distance.
    EXPECT_NEAR(signed_distance(x, Vector<T>(p * T(3))), expected, pick<T>(1e-12, 1e-4));
  }
  EXPECT_THROW((void)signed_distance(Vec3<T>(0, 0, 0), sphere<T>(Vec3<T>(0, 0, 0), T(1))),
               cgamesh::InvalidInputError);
}

TYPED_TEST(Geometry, SegmentPlaneIntersection) {
  using T = TypeParam;
  const T tol = pick<T>(1e-14, 1e-6);
  const Vector<T> p = plane<T>(Vec3<T>(0, 0, 2), T(2));  // z = 1
  // Crossing: from z = -1 to z = 3, the plane is reached halfway.
  const auto hit = segment_plane_intersection<T>(Vec3<T>(0, 0, -1), Vec3<T>(4, 2, 3), p);
  ASSERT_TRUE(hit.has_value());
  EXPECT_MAT_NEAR(*hit, Vec3<T>(2, 1, 1), tol);
  // Not reaching the plane, or entirely on one side.
  EXPECT_FALSE(segment_plane_intersection<T>(Vec3<T>(0, 0, -1), Vec3<T>(4, 2, 0.5), p).has_value());
  EXPECT_FALSE(segment_plane_intersection<T>(Vec3<T>(0, 0, 2), Vec3<T>(4, 2, 5), p).has_value());
  // Touching at one end: the end is returned.
  const auto touch = segment_plane_intersection<T>(Vec3<T>(3, 3, 1), Vec3<T>(0, 0, 5), p);
  ASSERT_TRUE(touch.has_value());
  EXPECT_MAT_NEAR(*touch, Vec3<T>(3, 3, 1), tol);
  const auto touch2 = segment_plane_intersection<T>(Vec3<T>(0, 0, -5), Vec3<T>(-1, 2, 1), p);
  ASSERT_TRUE(touch2.has_value());
  EXPECT_MAT_NEAR(*touch2, Vec3<T>(-1, 2, 1), tol);
  // Lying in the plane: no single crossing point.
  EXPECT_FALSE(segment_plane_intersection<T>(Vec3<T>(0, 0, 1), Vec3<T>(5, 5, 1), p).has_value());
  // Random crossings land on the plane and on the segment.
  Rng rng(303 + sizeof(T));
  int crossings = 0;
  for (int k = 0; k < 500; ++k) {
    const Vector<T> q = plane(random_unit<T>(rng), rng.uniform<T>(-1, 1));
    const Vec3<T> a = random_vec3<T>(rng, -3, 3), b = random_vec3<T>(rng, -3, 3);
    const T da = signed_distance(a, q), db = signed_distance(b, q);
    const auto x = segment_plane_intersection(a, b, q);
    ASSERT_EQ(x.has_value(), (da < 0) != (db < 0)) << "case " << k;
    if (!x) continue;
    ++crossings;
    EXPECT_NEAR(signed_distance(*x, q), T(0), pick<T>(1e-12, 1e-5));
    EXPECT_NEAR((*x - a).norm() + (b - *x).norm(), (b - a).norm(), pick<T>(1e-12, 1e-5));
  }
  EXPECT_GT(crossings, 100);
}

// ---------------------------------------------------------------- constructions from points

TYPED_TEST(Geometry, SphereThroughFourPoints) {
  using T = TypeParam;
  Rng rng(404 + sizeof(T));
  // Well-conditioned quadruples: a jittered, randomly rotated regular tetrahedron on a random
  // sphere.
  const std::array<Vec3<T>, 4> tetra{Vec3<T>(1, 1, 1), Vec3<T>(1, -1, -1), Vec3<T>(-1, 1, -1), Vec3<T>(-1, -1, 1)};
  for (int k = 0; k < 500; ++k) {
    const Vec3<T> c = random_vec3<T>(rng, -5, 5);
    const T r = rng.uniform<T>(0.5, 4);
    const Eigen::Matrix<T, 3, 3> rot = Eigen::AngleAxis<T>(rng.uniform<T>(0, 3), random_unit<T>(rng)).toRotationMatrix();
    std::array<Vec3<T>, 4> pts;
    for (int i = 0; i < 4; ++i) {
      const Vec3<T> dir = (rot * tetra[static_cast<std::size_t>(i)] + random_vec3<T>(rng, -0.3, 0.3)).normalized();
      pts[static_cast<std::size_t>(i)] = c + r * dir;
    }
    const Quadvector<T> outer = sphere_through(pts[0], pts[1], pts[2], pts[3]);
    const Vector<T> s = undual(outer);
    for (const auto& x : pts)
      EXPECT_NEAR(scalar_product(up(x), s), T(0), pick<T>(1e-12, 1e-4) * max_abs(s) * max_abs(up(x)));
    // The centre is equidistant from the four points, and is the generating centre.
    const auto sp = sphere_parameters(s);
    for (const auto& x : pts) EXPECT_NEAR((x - sp.center).norm(), sp.radius, pick<T>(1e-10, 1e-3));
    EXPECT_MAT_NEAR(sp.center, c, pick<T>(1e-10, 1e-3));
    EXPECT_NEAR(sp.radius, r, pick<T>(1e-10, 1e-3));
    // For the normalised sphere X . S = (r^2 - |x - c|^2) / 2: -3 r^2 / 2 at distance 2r.
    const T w = s.template get<blade::eo>();
    EXPECT_NEAR(scalar_product(up(Vec3<T>(c + Vec3<T>(0, 0, 2 * r))), s) / w, T(-1.5) * r * r,
                pick<T>(1e-9, 1e-2) * (T(1) + c.squaredNorm()));
  }
}

TYPED_TEST(Geometry, PlaneThroughThreePoints) {
  using T = TypeParam;
  Rng rng(505 + sizeof(T));
  const T tol = pick<T>(1e-11, 1e-3);
  for (int k = 0; k < 500; ++k) {
    const Vec3<T> a = random_vec3<T>(rng, -5, 5), b = random_vec3<T>(rng, -5, 5), c = random_vec3<T>(rng, -5, 5);
    const Vec3<T> cross = (b - a).cross(c - a);
    if (cross.norm() < T(1)) continue;  // nearly collinear
    const Vector<T> p = undual(plane_through(a, b, c));
    EXPECT_NEAR(p.template get<blade::eo>(), T(0), tol * max_abs(p));  // a plane has no eo part
    const auto [n, d] = plane_parameters(p);
    // As implemented, the normal of undual(A^B^C^einf) is +(b - a) x (c - a) normalised:
    // counter-clockwise a, b, c seen from the side the normal points to.
    EXPECT_MAT_NEAR(n, Vec3<T>(cross.normalized()), tol);
    EXPECT_NEAR(d, n.dot(a), tol * T(5));
    for (const Vec3<T>* x : {&a, &b, &c}) EXPECT_NEAR(signed_distance(*x, p), T(0), tol * T(10));
    // The plane is the undual of the outer form up to a factor: the same as plane(n, n . a).
    const auto [ref, other] = normalise_pair(p, plane(cross, cross.dot(a)));
    EXPECT_MV_NEAR(ref, other, tol * T(10));
  }
}

TYPED_TEST(Geometry, LinesAndCirclesContainTheirPoints) {
  using T = TypeParam;
  Rng rng(606 + sizeof(T));
  const T tol = pick<T>(1e-12, 1e-4);
  for (int k = 0; k < 500; ++k) {
    const Vec3<T> a = random_vec3<T>(rng, -5, 5), b = random_vec3<T>(rng, -5, 5), c = random_vec3<T>(rng, -5, 5);
    if ((b - a).cross(c - a).norm() < T(1)) continue;
    const Trivector<T> line = line_through(a, b);
    const Trivector<T> circle = circle_through(a, b, c);
    const T line_scale = max_abs(line), circle_scale = max_abs(circle);
    // Points on the line: a, b and any affine combination; the circle's three points.
    const T t = rng.uniform<T>(-2, 3);
    for (const Vec3<T>& x : {a, b, Vec3<T>(a + t * (b - a))}) {
      const auto q = up(x) ^ line;
      static_assert(decltype(q)::mask == mask::quadvector);
      EXPECT_MV_NEAR(q, Quadvector<T>(), tol * line_scale * max_abs(up(x)));
    }
    for (const Vec3<T>& x : {a, b, c}) EXPECT_MV_NEAR(up(x) ^ circle, Quadvector<T>(), tol * circle_scale * max_abs(up(x)));
    // c is off the line (not collinear), and the centroid is off the circle.
    EXPECT_GT(max_abs(up(c) ^ line), T(1e-3) * line_scale);
    const Vec3<T> centroid = (a + b + c) / T(3);
    EXPECT_GT(max_abs(up(centroid) ^ circle), T(1e-3) * circle_scale);
    // The line through a and b is the circle through a, b and infinity.
    EXPECT_MV_NEAR(line, up(a) ^ up(b) ^ einf<T>(), T(0));
  }
}

TEST(GeometryMeet, TwoSpheresAndAPlaneMeetInAPointPair) {
  // Spheres of radius 2 about the origin and (1,0,0), plane z = 0: points (0.5, +-sqrt(3.75), 0).
  const Vector<double> s1 = sphere<double>(Vec3<double>(0, 0, 0), 2.0), s2 = sphere<double>(Vec3<double>(1, 0, 0), 2.0);
  const Vector<double> p = plane<double>(Vec3<double>(0, 0, 1), 0.0);
  const Trivector<double> pp = meet(meet(s1, s2), p);
  const auto pts = point_pair_points(Bivector<double>(dual(pp)));
  const double y = std::sqrt(3.75);
  const bool order = pts[0].y() > 0;
  EXPECT_MAT_NEAR(pts[order ? 0 : 1], Vec3<double>(0.5, y, 0), 1e-12);
  EXPECT_MAT_NEAR(pts[order ? 1 : 0], Vec3<double>(0.5, -y, 0), 1e-12);

  // Random configurations through a known point x: spheres centred at c1, c2 through x and a
  // plane through x.
  Rng rng(707);
  for (int k = 0; k < 500; ++k) {
    const Vec3<double> x = random_vec3<double>(rng, -3, 3);
    const Vec3<double> c1 = random_vec3<double>(rng, -3, 3), c2 = random_vec3<double>(rng, -3, 3);
    const Vec3<double> n = random_unit<double>(rng);
    // Keep the configuration transversal: the centres apart and the plane not containing the
    // line of centres.
    if ((c1 - c2).norm() < 0.5 || std::abs(n.dot((c1 - c2).normalized())) > 0.9) continue;
    const Vector<double> a = sphere(c1, (x - c1).norm()), b = sphere(c2, (x - c2).norm()), q = plane(n, n.dot(x));
    const auto pair = point_pair_points(Bivector<double>(dual(meet(meet(a, b), q))));
    const double e0 = (pair[0] - x).norm(), e1 = (pair[1] - x).norm();
    EXPECT_LT(std::min(e0, e1), 1e-7) << "case " << k;
    for (const auto& pt : pair) {
      EXPECT_NEAR((pt - c1).norm(), (x - c1).norm(), 1e-7) << "case " << k;
      EXPECT_NEAR((pt - c2).norm(), (x - c2).norm(), 1e-7) << "case " << k;
      EXPECT_NEAR(signed_distance(pt, q), 0.0, 1e-7) << "case " << k;
    }
  }
}

TEST(GeometryMeet, TangentSpheresMeetInADoublePoint) {
  // Touching spheres and a plane through the touching point: P^2 = 0 up to rounding, which may
  // be negative; that is a tangent pair, not an imaginary one.
  const Vector<double> s1 = sphere<double>(Vec3<double>(0.1, 0.2, 0.3), 1.0);
  const Vector<double> s2 = sphere<double>(Vec3<double>(2.1, 0.2, 0.3), 1.0);
  const Vec3<double> n = Vec3<double>(0, 0.3, 1).normalized();
  const Bivector<double> pp = dual(meet(meet(s1, s2), plane(n, n.dot(Vec3<double>(1.1, 0.2, 0.3)))));
  for (const auto& pt : point_pair_points(pp)) EXPECT_MAT_NEAR(pt, Vec3<double>(1.1, 0.2, 0.3), 1e-12);
  Rng rng(717);
  for (int k = 0; k < 300; ++k) {
    const Vec3<double> c1 = random_vec3<double>(rng, -3, 3), u = random_unit<double>(rng);
    const double r1 = rng.uniform(0.5, 2.0), r2 = rng.uniform(0.5, 2.0);
    const Vec3<double> touch = c1 + r1 * u;
    const Vec3<double> m = random_unit<double>(rng);
    if (std::abs(m.dot(u)) > 0.9) continue;
    const Bivector<double> q =
        dual(meet(meet(sphere(c1, r1), sphere(Vec3<double>(c1 + (r1 + r2) * u), r2)), plane(m, m.dot(touch))));
    std::array<Vec3<double>, 2> pts;
    ASSERT_NO_THROW(pts = point_pair_points(q)) << "case " << k;
    for (const auto& pt : pts) EXPECT_MAT_NEAR(pt, touch, 1e-6) << "case " << k;
  }
}

TEST(GeometryMeet, PointPairOfOuterForm) {
  // point_pair_points of X1 ^ X2 returns the two points.
  Rng rng(808);
  for (int k = 0; k < 500; ++k) {
    const Vec3<double> a = random_vec3<double>(rng, -5, 5), b = random_vec3<double>(rng, -5, 5);
    if ((a - b).norm() < 0.1) continue;
    const auto pts = point_pair_points(Bivector<double>(up(a) ^ up(b)));
    const bool first_is_a = (pts[0] - a).norm() < (pts[1] - a).norm();
    EXPECT_MAT_NEAR(pts[first_is_a ? 0 : 1], a, 1e-10);
    EXPECT_MAT_NEAR(pts[first_is_a ? 1 : 0], b, 1e-10);
  }
}

TEST(GeometryMeet, ImaginaryPointPairThrows) {
  // Two disjoint spheres and a plane: no real intersection.
  const Vector<double> s1 = sphere<double>(Vec3<double>(0, 0, 0), 1.0), s2 = sphere<double>(Vec3<double>(5, 0, 0), 1.0);
  const Vector<double> p = plane<double>(Vec3<double>(0, 0, 1), 0.0);
  EXPECT_THROW((void)point_pair_points(Bivector<double>(dual(meet(meet(s1, s2), p)))), cgamesh::InvalidInputError);
  // Intersecting spheres but a plane that misses their circle.
  const Vector<double> s3 = sphere<double>(Vec3<double>(1, 0, 0), 1.0);
  const Vector<double> far = plane<double>(Vec3<double>(0, 0, 1), 3.0);
  EXPECT_THROW((void)point_pair_points(Bivector<double>(dual(meet(meet(s1, s3), far)))), cgamesh::InvalidInputError);
}

// ---------------------------------------------------------------- transformations vs Eigen

template <class T>
struct NamedTransform {
  Versor<T> versor;
  Eigen::Matrix<T, 3, 3> linear;  ///< s R
  Vec3<T> translation;
  T scale;
};

template <class T>
NamedTransform<T> random_transform(Rng& rng, int kind) {
  const Vec3<T> axis = random_unit<T>(rng);
  const T angle = rng.uniform<T>(-3, 3);
  const Vec3<T> t = random_vec3<T>(rng, -10, 10);
  const T s = rng.log_uniform<T>(T(0.2), T(5));
  using M3 = Eigen::Matrix<T, 3, 3>;
  switch (kind) {
    case 0: return {Versor<T>(rotor(axis, angle)), M3(Eigen::AngleAxis<T>(angle, axis).toRotationMatrix()), Vec3<T>::Zero(), T(1)};
    case 1: return {Versor<T>(translator(t)), M3::Identity(), t, T(1)};
    case 2: return {Versor<T>(dilator(s)), M3(s * M3::Identity()), Vec3<T>::Zero(), s};
    default: {
      const M3 lin = s * Eigen::AngleAxis<T>(angle, axis).toRotationMatrix();
      return {similarity(t, rotor(axis, angle), s), lin, t, s};
    }
  }
}

TYPED_TEST(Geometry, VersorsMatchMatrixTransforms) {
  using T = TypeParam;
  Rng rng(909 + sizeof(T));
  const T tol = pick<T>(1e-11, 2e-4);
  for (int k = 0; k < 1000; ++k) {
    const int kind = k % 4;
    SCOPED_TRACE(::testing::Message() << "case " << k << " kind " << kind);
    const auto tr = random_transform<T>(rng, kind);
    const auto f = [&](const Vec3<T>& x) { return Vec3<T>(tr.linear * x + tr.translation); };
    // Points.
    const Vec3<T> x = random_vec3<T>(rng, -5, 5);
    EXPECT_MAT_NEAR(transform_point(tr.versor, x), f(x), tol);
    // Spheres: the centre maps like a point, the radius scales.
    const Vec3<T> c = random_vec3<T>(rng, -5, 5);
    const T r = rng.uniform<T>(0.1, 3);
    const auto sp = sphere_parameters(sandwich(tr.versor, sphere(c, r)));
    EXPECT_MAT_NEAR(sp.center, f(c), tol);
    EXPECT_NEAR(sp.radius, tr.scale * r, tol * std::max(T(1), tr.scale * r));
    // Planes: the normal rotates, and a point of the plane stays on it.
    const Vec3<T> n = random_unit<T>(rng);
    const T d = rng.uniform<T>(-5, 5);
    const auto [n2, d2] = plane_parameters(sandwich(tr.versor, plane(n, d)));
    const Vec3<T> n_expected = (tr.linear * n).normalized();
    EXPECT_MAT_NEAR(n2, n_expected, tol);
    EXPECT_NEAR(d2, n_expected.dot(f(Vec3<T>(n * d))), tol * T(20));
  }
}

TYPED_TEST(Geometry, SandwichOfTheUnitVersorEqualsTheGeneralSandwich) {
  using T = TypeParam;
  Rng rng(1010 + sizeof(T));
  for (int k = 0; k < 200; ++k) {
    const auto tr = random_transform<T>(rng, 3);
    const Vector<T> x = up(random_vec3<T>(rng, -5, 5));
    EXPECT_MV_NEAR(unit_sandwich(tr.versor, x), sandwich(tr.versor, x), pick<T>(1e-12, 1e-4));
    // sandwich divides by <V ~V>: a scaled versor is the same transformation.
    EXPECT_MV_NEAR(sandwich(Versor<T>(tr.versor * T(3)), x), sandwich(tr.versor, x), pick<T>(1e-12, 1e-4));
  }
}

// ---------------------------------------------------------------- invalid inputs

TYPED_TEST(Geometry, ConstructorsRejectInvalidInput) {
  using T = TypeParam;
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  EXPECT_THROW((void)rotor(Vec3<T>(0, 0, 0), T(1)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)rotor(Vec3<T>(nan, 0, 1), T(1)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)rotor(Vec3<T>(0, 0, 1), nan), cgamesh::InvalidInputError);
  EXPECT_THROW((void)rotor(Vec3<T>(0, 0, 1), inf), cgamesh::InvalidInputError);
  EXPECT_THROW((void)plane(Vec3<T>(0, 0, 0), T(1)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)plane(Vec3<T>(nan, 0, 1), T(1)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)plane(Vec3<T>(0, 0, 1), nan), cgamesh::InvalidInputError);
  EXPECT_THROW((void)dilator(T(0)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)dilator(T(-2)), cgamesh::InvalidInputError);
  EXPECT_THROW((void)dilator(nan), cgamesh::InvalidInputError);
  EXPECT_THROW((void)dilator(inf), cgamesh::InvalidInputError);
  // Valid inputs just above the limits do not throw.
  EXPECT_NO_THROW((void)rotor(Vec3<T>(0, 0, T(1e-10)), T(1)));
  EXPECT_NO_THROW((void)dilator(T(1e-3)));
}

}  // namespace
