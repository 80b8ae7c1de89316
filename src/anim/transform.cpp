#include "cgamesh/anim/transform.hpp"

#include <cmath>

#include "cgamesh/cga/convert.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

#include "polar.hpp"

namespace cgamesh::anim {

Eigen::Matrix4d Transform::matrix() const {
  Eigen::Affine3d a = Eigen::Translation3d(translation) * rotation.normalized() * Eigen::Scaling(scale);
  return a.matrix();
}

double Transform::uniform_scale() const { return std::cbrt(std::abs(scale.x() * scale.y() * scale.z())); }

bool Transform::is_uniform(double tolerance) const {
  const double m = scale.cwiseAbs().maxCoeff();
  return (scale.array() - scale.x()).abs().maxCoeff() <= tolerance * m;
}

bool is_similarity(const Eigen::Matrix4d& m, double tolerance) {
  const Eigen::Matrix3d l = m.topLeftCorner<3, 3>();
  const Eigen::Matrix3d g = l.transpose() * l;
  const double s2 = g.trace() / 3;
  return s2 > 0 && (g - s2 * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 2 * tolerance * s2;
}

cga::Versor<double> Transform::versor() const {
  return cga::similarity(cga::Vec3<double>(translation), cga::rotor(rotation), uniform_scale());
}

Transform Transform::from_matrix(const Eigen::Matrix4d& m) {
  if (!m.allFinite()) throw InvalidInputError("transform matrix has NaN or infinite entries");
  const Eigen::Matrix3d a = m.topLeftCorner<3, 3>();
  const double det = a.determinant();
  if (!(std::abs(det) > 1e-300)) throw InvalidInputError("transform matrix is singular (zero scale)");
  // The polar decomposition of a mirror has a non-diagonal scale part: no TRS holds it.
  if (det < 0)
    throw InvalidInputError("transform matrix mirrors (negative determinant); a versor cannot hold a reflection");
  Eigen::Matrix3d r, s;
  detail::rotation_scaling(a, r, s);
  Transform t;
  t.translation = m.topRightCorner<3, 1>();
  t.rotation = Eigen::Quaterniond(r).normalized();
  t.scale = s.diagonal();
  return t;
}

Transform Transform::from_versor(const cga::Versor<double>& v) {
  const cga::SimilarityParts<double> p = cga::decompose(v);
  Transform t;
  t.translation = p.translation;
  t.rotation = cga::to_quaternion(p.rotation);
  t.scale = Eigen::Vector3d::Constant(p.scale);
  return t;
}

}  // namespace cgamesh::anim
