#pragma once
// FABRIK inverse kinematics for one chain (Aristidou & Lasenby 2011, used in paper section
// III.C / Fig. 5): the root stays, the end effector moves to the target, bone lengths are kept.
// The solved joints give one motor each, the key motors of a spline deformation.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"

namespace cgamesh::deform {

struct FabrikOptions {
  double tolerance = 1e-6;  ///< stop when the end effector is this close to the target
  int max_iterations = 100;
};

struct FabrikResult {
  bool reached = false;  ///< end effector within tolerance of the target
  int iterations = 0;
  double distance = 0;                  ///< final end effector - target distance
  std::vector<Eigen::Vector3d> joints;  ///< #J solved joint positions
  /// #J motors taking the rest chain to the solved one: M_i = T(p_i) R_i T(-rest_i), R_i the
  /// shortest rotation of the rest bone leaving joint i onto the solved one (the last joint
  /// takes its incoming bone's rotation).
  std::vector<cga::Motor<double>> motors;
};

/// Solves the chain; when the target is out of reach the chain points straight at it and
/// `reached` is false.
/// @param[in] joints  #J >= 2 rest joint positions, root first
/// @param[in] target  end effector goal
/// @throws InvalidInputError for fewer than 2 joints, a zero-length bone, a non-finite
///         coordinate, or a tolerance that is not positive.
[[nodiscard]] FabrikResult fabrik(std::span<const Eigen::Vector3d> joints, const Eigen::Vector3d& target,
                                  const FabrikOptions& options = {});

}  // namespace cgamesh::deform
