#pragma once
// The shared half of the methods whose handles select control points (ffd: lattice points; cage:
// cage vertices): each point under the keys of the handles that select it, composed in handle
// order, then the deformer's classic (points, eq. 6) or motor (eqs. 7-8) frame.

#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "deform_method.hpp"

namespace cgamesh::deform::detail {

/// Each point under the keys (maps) of the handles that select it, composed in handle order.
[[nodiscard]] inline std::vector<Eigen::Vector3d> moved_points(const std::vector<std::vector<int>>& keys_of_point,
                                                               std::span<const cga::Versor<double>> keys,
                                                               std::vector<Eigen::Vector3d> points) {
  std::vector<Eigen::Matrix<double, 3, 4>> maps;
  for (const auto& k : keys) maps.push_back(cga::PointMap<double>(k).affine_matrix());
  for (std::size_t c = 0; c < points.size(); ++c)
    for (const int h : keys_of_point[c]) {
      const Eigen::Matrix<double, 3, 4>& m = maps[static_cast<std::size_t>(h)];
      points[c] = m.leftCols<3>() * points[c] + m.col(3);
    }
  return points;
}

/// `Deformer` is FreeFormDeformation or CageDeformation (deform_points, deform_motors).
template <class Deformer>
class ControlPointMethod : public BoundMethod {
 public:
  /// @param[in] deformer       the bound lattice or cage
  /// @param[in] variant        classic or motor
  /// @param[in] keys_of_point  per control point, the handles that select it, ascending
  /// @param[in] points         the control points before the keys (classic: the deformed cage)
  ControlPointMethod(Deformer deformer, FfdVariant variant, std::vector<std::vector<int>> keys_of_point,
                     std::vector<Eigen::Vector3d> points)
      : deformer_(std::move(deformer)),
        variant_(variant),
        keys_of_point_(std::move(keys_of_point)),
        points_(std::move(points)) {}

 protected:
  Deformer deformer_;

 private:
  void apply(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out, ArapReport*) const final {
    if (variant_ == FfdVariant::motor) {
      std::vector<cga::Versor<double>> motors(keys_of_point_.size(),
                                              cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>()));
      for (std::size_t c = 0; c < motors.size(); ++c)
        for (const int h : keys_of_point_[c])
          motors[c] = cga::project<cga::mask::versor>(keys[static_cast<std::size_t>(h)] * motors[c]);
      deformer_.deform_motors(motors, out);
      return;
    }
    (void)similarity_logs(keys);  // the classic variant takes similarities too, so that either variant fails alike
    deformer_.deform_points(moved_points(keys_of_point_, keys, points_), out);
  }

  [[nodiscard]] std::vector<Eigen::Vector3d> control_points(std::span<const cga::Versor<double>> keys) const final {
    return moved_points(keys_of_point_, keys, points_);
  }

  FfdVariant variant_;
  std::vector<std::vector<int>> keys_of_point_;
  std::vector<Eigen::Vector3d> points_;
};

/// "variant" of the ffd and cage methods.
[[nodiscard]] inline FfdVariant parse_variant(const Json& j) {
  return choice<FfdVariant>(j, "variant", {{"classic", FfdVariant::classic}, {"motor", FfdVariant::motor}},
                            FfdVariant::motor);
}

}  // namespace cgamesh::deform::detail
