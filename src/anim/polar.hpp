#pragma once
// Private to the library: the polar decomposition of a 3×3 matrix, for the TRS split of joint
// matrices and for the dual quaternions of the dqs palette (once per joint per frame).

#include <Eigen/Core>

namespace cgamesh::detail {

/// l = r s with r a rotation and s symmetric; a mirror goes into s. The same decomposition as
/// Eigen's computeRotationScaling (an SVD), found by Newton's iteration r <- (g r + (g r)^-T) / 2
/// (g = |det r|^(-1/3)) when det l > 0: on the near-rotations of rigid rigs it settles in one or
/// two steps, about 20 times faster than the SVD. Mirrors, singular and non-finite matrices, and
/// an iteration that does not settle, take the SVD.
/// @param[in]  l  3×3 linear part
/// @param[out] r  3×3 rotation
/// @param[out] s  3×3 symmetric scale/shear
void rotation_scaling(const Eigen::Matrix3d& l, Eigen::Matrix3d& r, Eigen::Matrix3d& s);

}  // namespace cgamesh::detail
