#include "cgamesh/deform/fabrik.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::deform {
namespace {

/// Shortest rotation taking direction a onto direction b (any axis normal to a at 180 degrees).
cga::Rotor<double> rotation_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ua = a.normalized(), ub = b.normalized();
  const Eigen::Vector3d axis = ua.cross(ub);
  const double angle = std::atan2(axis.norm(), ua.dot(ub));
  if (axis.norm() > 1e-12) return cga::rotor(axis, angle);
  if (angle < 1.0) return cga::Rotor<double>({1.0, 0.0, 0.0, 0.0});
  const Eigen::Vector3d any = std::abs(ua.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return cga::rotor(Eigen::Vector3d(ua.cross(any)), angle);
}

/// Puts `next` at distance `length` from `from`, on the ray towards `next` (or `fallback`).
void place(const Eigen::Vector3d& from, Eigen::Vector3d& next, double length, const Eigen::Vector3d& fallback) {
  const Eigen::Vector3d d = next - from;
  const double r = d.norm();
  next = from + length * (r > 0 ? Eigen::Vector3d(d / r) : fallback.normalized());
}

}  // namespace

FabrikResult fabrik(std::span<const Eigen::Vector3d> joints, const Eigen::Vector3d& target,
                    const FabrikOptions& options) {
  const std::size_t n = joints.size();
  if (n < 2) throw InvalidInputError("FABRIK: a chain needs at least 2 joints, got " + std::to_string(n));
  if (!target.allFinite()) throw InvalidInputError("FABRIK: the target is not finite");
  if (!(options.tolerance > 0)) throw InvalidInputError("FABRIK: the tolerance must be > 0");
  std::vector<double> length(n - 1);
  double total = 0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (!joints[i].allFinite() || !joints[i + 1].allFinite())
      throw InvalidInputError("FABRIK: joint " + std::to_string(i) + " is not finite");
    length[i] = (joints[i + 1] - joints[i]).norm();
    if (!(length[i] > 0)) throw InvalidInputError("FABRIK: bone " + std::to_string(i) + " has zero length");
    total += length[i];
  }
  FabrikResult result;
  std::vector<Eigen::Vector3d>& p = result.joints;
  p.assign(joints.begin(), joints.end());
  const Eigen::Vector3d root = p[0];
  const auto rest_bone = [&](std::size_t i) { return Eigen::Vector3d(joints[i + 1] - joints[i]); };
  if ((target - root).norm() > total) {
    for (std::size_t i = 0; i + 1 < n; ++i) {
      p[i + 1] = target;
      place(p[i], p[i + 1], length[i], rest_bone(i));
    }
  } else {
    for (; result.iterations < options.max_iterations && (p[n - 1] - target).norm() > options.tolerance;
         ++result.iterations) {
      p[n - 1] = target;  // backward: from the end effector to the root
      for (std::size_t i = n - 1; i-- > 0;) place(p[i + 1], p[i], length[i], Eigen::Vector3d(-rest_bone(i)));
      p[0] = root;  // forward: from the root to the end effector
      for (std::size_t i = 0; i + 1 < n; ++i) place(p[i], p[i + 1], length[i], rest_bone(i));
    }
  }
  result.distance = (p[n - 1] - target).norm();
  result.reached = result.distance <= options.tolerance;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t bone = std::min(i, n - 2);
    const cga::Rotor<double> r = rotation_between(rest_bone(bone), p[bone + 1] - p[bone]);
    result.motors.push_back(
        cga::project<cga::mask::motor>(cga::translator(p[i]) * r * cga::translator(Eigen::Vector3d(-joints[i]))));
  }
  return result;
}

}  // namespace cgamesh::deform
