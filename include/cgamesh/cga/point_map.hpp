#pragma once
// A versor's sandwich as a linear map, for transforming many points by one versor.
//
// X -> V X V^-1 is linear on vectors: a 5x5 matrix in the basis (e1, e2, e3, einf, eo), built
// from the sandwiches of the five basis vectors. For a similarity (any composition of
// translations, rotations and dilations) einf maps to a multiple of itself and eo gains no
// einf-free Euclidean part beyond a translation, so down(V up(x) V^-1) = A x + b: a 3x4
// affine matrix, as cheap as the matrix pipeline. Other conformal maps (transversions,
// inversions) keep the general rational form.

#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::cga {

template <class T>
class PointMap {
 public:
  /// The map of x -> down(V up(x) V^-1).
  /// @param[in] v  invertible versor (even or odd)
  /// @throws InvalidInputError when v is not invertible.
  template <BladeMask M>
  explicit PointMap(const Multivector<T, M>& v) {
    const Multivector<T, M> vi = versor_inverse(v);
    [&]<std::size_t... J>(std::index_sequence<J...>) {
      ((matrix_.col(J) = column(product_part<mask::vector>(v * basis_blade<T, BladeIndex{1} << J>(), vi))), ...);
    }
    (std::make_index_sequence<kDimension>{});
    // Rows/cols: 0..2 Euclidean, 3 einf, 4 eo. Affine when the x^2 (einf) column has no
    // Euclidean or eo part and the eo row depends on nothing but eo.
    const T scale = matrix_.cwiseAbs().maxCoeff();
    const T tol = scale * std::numeric_limits<T>::epsilon() * T(64);
    const T w = matrix_(4, 4);
    affine_ = std::abs(w) > tol && matrix_.template block<3, 1>(0, 3).cwiseAbs().maxCoeff() <= tol &&
              matrix_.template block<1, 4>(4, 0).cwiseAbs().maxCoeff() <= tol;
    if (affine_) {
      affine_matrix_.template leftCols<3>() = matrix_.template topLeftCorner<3, 3>() / w;
      affine_matrix_.col(3) = matrix_.template block<3, 1>(0, 4) / w;
    }
  }

  /// The 5x5 matrix of the sandwich on vectors, basis (e1, e2, e3, einf, eo).
  [[nodiscard]] const Eigen::Matrix<T, 5, 5>& matrix() const noexcept { return matrix_; }
  /// True for similarities: then points map by affine_matrix().
  [[nodiscard]] bool is_affine() const noexcept { return affine_; }
  /// [A b] with x' = A x + b; meaningful when is_affine().
  [[nodiscard]] const Eigen::Matrix<T, 3, 4>& affine_matrix() const noexcept { return affine_matrix_; }

  /// One point.
  /// @throws InvalidInputError when a non-affine map sends the point to infinity.
  [[nodiscard]] Vec3<T> operator()(const Vec3<T>& x) const {
    if (affine_) return affine_matrix_.template leftCols<3>() * x + affine_matrix_.col(3);
    Eigen::Matrix<T, 5, 1> xc;
    xc << x, T(0.5) * x.squaredNorm(), T(1);
    const Eigen::Matrix<T, 5, 1> y = matrix_ * xc;
    if (!(std::abs(y(4)) > std::numeric_limits<T>::min()))
      throw InvalidInputError("PointMap: the conformal map sends a point to infinity");
    return y.template head<3>() / y(4);
  }

  /// Many points, packed x y z x y z ...
  /// @param[in]  in   #n*3 coordinates
  /// @param[out] out  #n*3 coordinates (may alias in)
  /// @throws InvalidInputError when the sizes differ or are not multiples of 3.
  void apply(std::span<const T> in, std::span<T> out) const {
    if (in.size() != out.size() || in.size() % 3 != 0)
      throw InvalidInputError("PointMap::apply: input and output must hold the same number of xyz triples (got " +
                              std::to_string(in.size()) + " and " + std::to_string(out.size()) + " values)");
    const std::size_t n = in.size() / 3;
    if (affine_) {
      const Eigen::Matrix<T, 3, 4> m = affine_matrix_;
      for (std::size_t i = 0; i < n; ++i) {
        const T x = in[3 * i], y = in[3 * i + 1], z = in[3 * i + 2];
        out[3 * i] = m(0, 0) * x + m(0, 1) * y + m(0, 2) * z + m(0, 3);
        out[3 * i + 1] = m(1, 0) * x + m(1, 1) * y + m(1, 2) * z + m(1, 3);
        out[3 * i + 2] = m(2, 0) * x + m(2, 1) * y + m(2, 2) * z + m(2, 3);
      }
      return;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3<T> p = (*this)(Vec3<T>(in[3 * i], in[3 * i + 1], in[3 * i + 2]));
      out[3 * i] = p.x();
      out[3 * i + 1] = p.y();
      out[3 * i + 2] = p.z();
    }
  }

 private:
  static Eigen::Matrix<T, 5, 1> column(const Vector<T>& y) noexcept {
    return Eigen::Matrix<T, 5, 1>(y[0], y[1], y[2], y[3], y[4]);
  }

  Eigen::Matrix<T, 5, 5> matrix_;
  Eigen::Matrix<T, 3, 4> affine_matrix_ = Eigen::Matrix<T, 3, 4>::Zero();
  bool affine_ = false;
};

/// [A b] of PointMap(m) for a motor m = T R (a rigid motion at any scale, as eq. (17)'s M_n B_n
/// without dilations): A from the unit rotor's sandwiches R e_j ~R (j = 1, 2, 3), b the
/// translation of T (`decompose`). The same map as PointMap's five sandwiches of the motor, in
/// about a quarter of the products.
/// @param[in] m  motor: a product of rotors and translators times a nonzero scalar
/// @throws InvalidInputError when m has no rotor part (it is not a motor).
template <class T>
[[nodiscard]] Eigen::Matrix<T, 3, 4> motor_affine_matrix(const Motor<T>& m) {
  const SimilarityParts<T> parts = decompose(m);
  const auto image = [&](const auto& e) {
    const Vector<T> y = unit_sandwich(parts.rotation, e);
    return Vec3<T>(y[0], y[1], y[2]);
  };
  Eigen::Matrix<T, 3, 4> a;
  a << image(basis_blade<T, blade::e1>()), image(basis_blade<T, blade::e2>()), image(basis_blade<T, blade::e3>()),
      parts.translation;
  return a;
}

}  // namespace cgamesh::cga
