#include "polar.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace cgamesh::detail {

void rotation_scaling(const Eigen::Matrix3d& l, Eigen::Matrix3d& r, Eigen::Matrix3d& s) {
  r = l;
  // Quadratic convergence from the first step on (the scaling g makes det r = 1 at each step):
  // a few steps even for scales far from 1; the bound only stops a pathological matrix. A
  // mirror, a singular or a non-finite l fails the determinant test at once.
  for (int step = 0; step < 40; ++step) {
    const double det = r.determinant();
    if (!(det > 0) || !std::isfinite(det)) break;
    const double g = 1.0 / std::cbrt(det);
    const Eigen::Matrix3d next = 0.5 * (g * r + (g * r).inverse().transpose());
    const double change = (next - r).cwiseAbs().maxCoeff();
    r = next;
    if (change <= 1e-9) {  // the step after a change of e leaves an error of about e²
      s = r.transpose() * l;
      return;
    }
  }
  Eigen::Affine3d a = Eigen::Affine3d::Identity();
  a.linear() = l;
  a.computeRotationScaling(&r, &s);
}

}  // namespace cgamesh::detail
