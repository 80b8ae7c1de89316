#pragma once
// A joint's local transform as files store it: translation, rotation, scale (TRS).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cgamesh/cga/multivector.hpp"

namespace cgamesh::anim {

/// Relative tolerance below which a scale counts as uniform: the loader's warnings, the versors'
/// geometric mean and the skinning's choice of exact maps agree on it. Float files leave up to a
/// few 1e-6 of noise on rigid rigs (CesiumMan's inverse binds).
inline constexpr double kUniformScaleTolerance = 1e-5;

/// x -> T(translation) R(rotation) S(scale) x. The scale may be non-uniform, as files allow;
/// a CGA versor holds only its geometric mean (see uniform_scale()).
struct Transform {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();

  /// The 4x4 matrix T R S (exact, non-uniform scale included).
  [[nodiscard]] Eigen::Matrix4d matrix() const;
  /// Geometric mean |sx sy sz|^(1/3): the uniform scale that keeps the volume.
  [[nodiscard]] double uniform_scale() const;
  /// True when the three scale factors agree to a relative `tolerance`.
  [[nodiscard]] bool is_uniform(double tolerance = kUniformScaleTolerance) const;
  /// The versor T R D(uniform_scale()) (eq. 10, 8, 12 composed as in eq. 14).
  [[nodiscard]] cga::Versor<double> versor() const;

  /// Splits a 4x4 affine matrix into TRS (polar decomposition).
  /// @throws InvalidInputError for a singular, mirroring (negative determinant) or non-finite
  ///         matrix; the loader makes mirrored nodes proper before (io/model_loader.hpp).
  [[nodiscard]] static Transform from_matrix(const Eigen::Matrix4d& m);
  /// The TRS of a similarity versor.
  [[nodiscard]] static Transform from_versor(const cga::Versor<double>& v);
};

/// Whether the 4x4 affine matrix `m` is a similarity x -> s R x + t (what a CGA versor holds
/// exactly): L^T L = s^2 I for its linear part L, to a relative `tolerance` on the scale (twice
/// that on s^2). Non-uniform scale and shear are not.
[[nodiscard]] bool is_similarity(const Eigen::Matrix4d& m, double tolerance = kUniformScaleTolerance);

}  // namespace cgamesh::anim
