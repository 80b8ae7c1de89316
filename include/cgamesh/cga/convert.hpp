#pragma once
// Conversions between CGA versors and the representations engines use: 4x4 matrices (rigid
// motion with uniform scale), unit quaternions and unit dual quaternions.
//
// Sign conventions:
// - Quaternion q = (w, x, y, z) rotates v to q v q*; the rotor of the same rotation is
//   R = w - x e23 + y e13 - z e12 (eq. 8 with q = (cos a/2, sin a/2 u)). q and -q, like R and
//   -R, are the same rotation; conversions keep the sign.
// - Matrices are Eigen column-vector matrices: x' = M [x; 1], M = [s R, t; 0 0 0 1].
// - Dual quaternion dq = qr + eps qd for x' = qr x qr* + t, with qd = (1/2) t qr; the motor is
//   T(t) R(qr).

#include <cmath>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::cga {

/// Unit dual quaternion real + eps dual (see the conventions above).
template <class T>
struct DualQuaternion {
  Eigen::Quaternion<T> real;
  Eigen::Quaternion<T> dual;
};

/// Rotor of a quaternion (normalised first).
/// @throws InvalidInputError for a zero or non-finite quaternion.
template <class T>
[[nodiscard]] Rotor<T> rotor(const Eigen::Quaternion<T>& q) {
  const T n = q.norm();
  if (!(n > T(0)) || !std::isfinite(n)) throw InvalidInputError("rotor: the quaternion is zero or not finite");
  return Rotor<T>({q.w() / n, -q.z() / n, q.y() / n, -q.x() / n});
}
/// Quaternion of a unit rotor.
template <class T>
[[nodiscard]] Eigen::Quaternion<T> to_quaternion(const Rotor<T>& r) noexcept {
  return Eigen::Quaternion<T>(r[0], -r.template get<blade::e23>(), r.template get<blade::e13>(),
                              -r.template get<blade::e12>());
}

/// TRS versor of a 4x4 similarity matrix [s R, t; 0 0 0 1].
/// @throws InvalidInputError when M is not finite, its last row is not (0 0 0 1), or its 3x3
///         part is not a positive uniform scale times a rotation (shear, non-uniform scale or
///         a reflection), to a relative tolerance `tolerance`.
template <class T>
[[nodiscard]] Versor<T> versor_from_matrix(const Eigen::Matrix<T, 4, 4>& m, T tolerance = T(1e-4)) {
  if (!m.allFinite()) throw InvalidInputError("versor_from_matrix: the matrix has NaN or infinite entries");
  if (m.row(3).template head<3>().cwiseAbs().maxCoeff() > tolerance || std::abs(m(3, 3) - T(1)) > tolerance)
    throw InvalidInputError("versor_from_matrix: the last row is not (0 0 0 1): a projective matrix");
  const Eigen::Matrix<T, 3, 3> a = m.template topLeftCorner<3, 3>();
  const T det = a.determinant();
  if (!(det > T(0)))
    throw InvalidInputError("versor_from_matrix: the matrix is singular or mirrors (det <= 0); a versor of "
                            "translation, rotation and positive uniform scale cannot represent it");
  const T s = std::cbrt(det);
  const Eigen::Matrix<T, 3, 3> r = a / s;
  if (((r.transpose() * r) - Eigen::Matrix<T, 3, 3>::Identity()).cwiseAbs().maxCoeff() > tolerance)
    throw InvalidInputError("versor_from_matrix: the matrix has shear or non-uniform scale; a CGA versor holds "
                            "only uniform scale");
  return similarity(Vec3<T>(m.template topRightCorner<3, 1>()), rotor(Eigen::Quaternion<T>(r)), s);
}

/// 4x4 matrix [s R, t; 0 0 0 1] of a TRS versor.
/// @throws InvalidInputError when v is not the versor of a similarity.
template <class T>
[[nodiscard]] Eigen::Matrix<T, 4, 4> to_matrix(const Versor<T>& v) {
  const SimilarityParts<T> p = decompose(v);
  Eigen::Matrix<T, 4, 4> m = Eigen::Matrix<T, 4, 4>::Identity();
  m.template topLeftCorner<3, 3>() = p.scale * to_quaternion(p.rotation).toRotationMatrix();
  m.template topRightCorner<3, 1>() = p.translation;
  return m;
}

/// Motor of a unit dual quaternion.
/// @throws InvalidInputError for a zero or non-finite real part.
template <class T>
[[nodiscard]] Motor<T> motor(const DualQuaternion<T>& dq) {
  const T n = dq.real.norm();
  if (!(n > T(0)) || !std::isfinite(n) || !dq.dual.coeffs().allFinite())
    throw InvalidInputError("motor: the dual quaternion's real part is zero or not finite");
  const Eigen::Quaternion<T> t = Eigen::Quaternion<T>(dq.dual.coeffs() * (T(2) / n)) * dq.real.conjugate();
  return translator(Vec3<T>(t.vec() / n)) * rotor(dq.real);
}
/// Unit dual quaternion of a unit motor.
template <class T>
[[nodiscard]] DualQuaternion<T> to_dual_quaternion(const Motor<T>& m) {
  const SimilarityParts<T> p = decompose(m);
  const Eigen::Quaternion<T> qr = to_quaternion(p.rotation);
  const Eigen::Quaternion<T> t(T(0), p.translation.x(), p.translation.y(), p.translation.z());
  return {qr, Eigen::Quaternion<T>((t * qr).coeffs() * T(0.5))};
}

}  // namespace cgamesh::cga
