#pragma once
// Geometric objects of CGA (paper sections 2.1 and 2.3): points, spheres and planes as vectors,
// their outer-product ("dual" in the paper) constructions from points, intersections by outer
// products, point pairs, and distances.
//
// Naming: a *vector form* is the paper's normal form (X . S = 0 for points X on the object);
// an *outer form* is the outer product of points on it (the paper's dual form). They are
// related by dual/undual up to a scalar factor.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::cga {

/// Up-projection of a Euclidean point (eq. 3): X = x + (1/2) x^2 einf + eo.
template <class T>
[[nodiscard]] constexpr Vector<T> up(const Vec3<T>& x) noexcept {
  return make_vector<T>(x.x(), x.y(), x.z(), T(0.5) * x.squaredNorm(), T(1));
}

/// Down-projection of a conformal point: normalise by -X . einf (the eo coefficient) and
/// read the Euclidean part.
/// @throws InvalidInputError when X is not a finite point: its eo coefficient is zero (a
///         plane, a direction or the point at infinity), it is not null (a sphere), or NaN.
template <class T>
[[nodiscard]] Vec3<T> down(const Vector<T>& x) {
  if (!is_finite(x)) throw InvalidInputError("down: the conformal vector has a NaN or infinite coefficient");
  const T w = x.template get<blade::eo>();
  // Not max_abs(x): the einf coefficient grows like |x|^2 and would reject far points (in
  // float from |x| ~ 1e3). A non-point that passes is caught by the null test below.
  const T scale = std::max({std::abs(x[0]), std::abs(x[1]), std::abs(x[2]), std::abs(w)});
  if (!(std::abs(w) > scale * std::numeric_limits<T>::epsilon() * T(16)))
    throw InvalidInputError("down: not a finite point (its eo coefficient is zero: a plane, a direction or infinity)");
  const Vector<T> n = x / w;
  const Vec3<T> p(n[0], n[1], n[2]);
  // A point is null; a sphere of radius r has X^2 = r^2.
  const T sq = scalar_product(n, n);
  const T tol = std::sqrt(std::numeric_limits<T>::epsilon()) * (T(1) + p.squaredNorm());
  if (std::abs(sq) > tol)
    throw InvalidInputError("down: not a point (X^2 = " + std::to_string(sq) + " != 0: a sphere or imaginary sphere)");
  return p;
}

/// Sphere with centre c and radius r (eq. 4): S = up(c) - (1/2) r^2 einf. r = 0 gives the point.
template <class T>
[[nodiscard]] constexpr Vector<T> sphere(const Vec3<T>& c, T r) noexcept {
  return up(c) - T(0.5) * r * r * einf<T>();
}

/// Plane with normal n at signed distance d from the origin (eq. 5): P = n + d einf, so that
/// X . P = n . x - d for a normalised point X = up(x): zero exactly on the plane n . x = d.
/// The normal is normalised, so X . P is the signed Euclidean distance.
/// @throws InvalidInputError for a zero or non-finite normal or a non-finite d.
template <class T>
[[nodiscard]] Vector<T> plane(const Vec3<T>& n, T d) {
  detail::require_finite(n, "plane normal");
  detail::require_finite(d, "plane distance");
  const T len = n.norm();
  if (!(len > T(0))) throw InvalidInputError("plane: the normal is the zero vector");
  return make_vector<T>(n.x() / len, n.y() / len, n.z() / len, d / len, T(0));
}

/// Outer form of the sphere through four points: X1^X2^X3^X4 (section 2.3).
template <class T>
[[nodiscard]] constexpr Quadvector<T> sphere_through(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c,
                                                     const Vec3<T>& d) noexcept {
  return up(a) ^ up(b) ^ up(c) ^ up(d);
}
/// Outer form of the plane through three points: X1^X2^X3^einf.
template <class T>
[[nodiscard]] constexpr Quadvector<T> plane_through(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) noexcept {
  return up(a) ^ up(b) ^ up(c) ^ einf<T>();
}
/// Outer form of the line through two points: X1^X2^einf.
template <class T>
[[nodiscard]] constexpr Trivector<T> line_through(const Vec3<T>& a, const Vec3<T>& b) noexcept {
  return up(a) ^ up(b) ^ einf<T>();
}
/// Outer form of the circle through three points: X1^X2^X3.
template <class T>
[[nodiscard]] constexpr Trivector<T> circle_through(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) noexcept {
  return up(a) ^ up(b) ^ up(c);
}

/// Centre and radius of a sphere.
template <class T>
struct SphereParameters {
  Vec3<T> center;
  T radius;
};

/// Centre and radius of a sphere in vector form (any scalar multiple of eq. 4).
/// @throws InvalidInputError for a plane (no eo part) or an imaginary sphere (r^2 < 0).
template <class T>
[[nodiscard]] SphereParameters<T> sphere_parameters(const Vector<T>& s) {
  const T w = s.template get<blade::eo>();
  if (!(std::abs(w) > max_abs(s) * std::numeric_limits<T>::epsilon() * T(16)))
    throw InvalidInputError("sphere_parameters: the vector has no eo part (it is a plane, not a sphere)");
  const Vector<T> n = s / w;
  const T r2 = scalar_product(n, n);
  const T tol = std::numeric_limits<T>::epsilon() * T(64) * (T(1) + std::abs(n.template get<blade::einf>()));
  if (r2 < -tol) throw InvalidInputError("sphere_parameters: imaginary sphere (r^2 = " + std::to_string(r2) + ")");
  return {Vec3<T>(n[0], n[1], n[2]), std::sqrt(std::max(r2, T(0)))};
}

/// Unit normal n and distance d of a plane in vector form (any multiple of eq. 5): n . x = d.
/// @throws InvalidInputError when the vector is not a plane (it has an eo part or no normal).
template <class T>
[[nodiscard]] std::pair<Vec3<T>, T> plane_parameters(const Vector<T>& p) {
  const Vec3<T> n(p[0], p[1], p[2]);
  const T len = n.norm();
  if (!(len > T(0)) || !std::isfinite(len)) throw InvalidInputError("plane_parameters: the plane has no normal");
  if (std::abs(p.template get<blade::eo>()) > len * std::sqrt(std::numeric_limits<T>::epsilon()))
    throw InvalidInputError("plane_parameters: the vector has an eo part (it is a sphere, not a plane)");
  return {n / len, p.template get<blade::einf>() / len};
}

/// Intersection of objects in vector form by their outer product (section 2.2): two spheres or
/// planes give a circle or line (bivector), three give a point pair (trivector).
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr auto meet(const Multivector<T, A>& a, const Multivector<T, B>& b) noexcept {
  return a ^ b;
}

/// The two points of a point pair in outer form P = X1^X2 (for a point pair in vector form,
/// e.g. the meet of three spheres, pass dual(pp)). With delta = sqrt(P^2),
/// X1 ~ (P - delta)(einf _| P) and X2 ~ (P + delta)(einf _| P).
/// @throws InvalidInputError when the pair is imaginary (P^2 < 0: the objects do not meet) or
///         degenerate (einf _| P = 0: a pair at infinity).
template <class T>
[[nodiscard]] std::array<Vec3<T>, 2> point_pair_points(const Bivector<T>& p) {
  const T p2 = scalar_product(p, p);
  // Rounding scale of P^2 (not P^2 itself, = -norm_squared(p), against which no negative
  // rounding error could ever pass: tangent objects would be reported as not meeting).
  const T tol = std::numeric_limits<T>::epsilon() * T(64) * max_abs(p) * max_abs(p);
  if (p2 < -std::abs(tol)) throw InvalidInputError("point_pair_points: imaginary point pair (the objects do not meet)");
  const T delta = std::sqrt(std::max(p2, T(0)));
  const Vector<T> d = left_contraction(einf<T>(), p);
  if (max_abs(d) == T(0)) throw InvalidInputError("point_pair_points: the point pair lies at infinity");
  const Vector<T> x1 = grade_part<1>((p - Scalar<T>({delta})) * d);
  const Vector<T> x2 = grade_part<1>((p + Scalar<T>({delta})) * d);
  return {down(x1), down(x2)};
}

/// Signed Euclidean distance of point x from plane P (vector form): X . P / |n|; positive on
/// the side the normal points to.
/// @throws InvalidInputError when P is not a plane.
template <class T>
[[nodiscard]] T signed_distance(const Vec3<T>& x, const Vector<T>& p) {
  const auto [n, d] = plane_parameters(p);
  return scalar_product(up(x), make_vector<T>(n.x(), n.y(), n.z(), d, T(0)));
}

/// Point where segment [a, b] crosses plane P, or nothing when both ends are strictly on the
/// same side (or the segment lies in the plane). Computed from the signed distances X . P.
/// @throws InvalidInputError when P is not a plane.
template <class T>
[[nodiscard]] std::optional<Vec3<T>> segment_plane_intersection(const Vec3<T>& a, const Vec3<T>& b,
                                                                const Vector<T>& p) {
  const T da = signed_distance(a, p);
  const T db = signed_distance(b, p);
  if ((da > 0 && db > 0) || (da < 0 && db < 0) || (da == 0 && db == 0)) return std::nullopt;
  const T t = da / (da - db);
  return a + t * (b - a);
}

}  // namespace cgamesh::cga
