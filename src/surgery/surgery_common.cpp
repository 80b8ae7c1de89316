#include "surgery_common.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <unordered_map>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::surgery {

std::uint64_t edge_key(int a, int b) noexcept {
  const auto [lo, hi] = std::minmax(a, b);
  return directed_key(lo, hi);
}

std::uint64_t directed_key(int a, int b) noexcept {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

std::vector<double> signed_distances(const mesh::RowMatrixXf<3>& placed, const Eigen::Vector3d& n, double d,
                                     const cga::Vector<double>& plane, Predicates predicates) {
  std::vector<double> out(static_cast<std::size_t>(placed.rows()));
  if (predicates == Predicates::cga) {
    for (Eigen::Index i = 0; i < placed.rows(); ++i)
      out[static_cast<std::size_t>(i)] = cga::scalar_product(cga::up<double>(placed.row(i).cast<double>().transpose()), plane);
  } else {
    for (Eigen::Index i = 0; i < placed.rows(); ++i)
      out[static_cast<std::size_t>(i)] = n.dot(placed.row(i).cast<double>().transpose()) - d;
  }
  return out;
}

double bounding_diagonal(const mesh::RowMatrixXf<3>& points) {
  if (points.rows() == 0) return 0;
  return static_cast<double>((points.colwise().maxCoeff() - points.colwise().minCoeff()).norm());
}

std::size_t PositionWelder::Hash::operator()(const std::array<float, 3>& p) const noexcept {
  std::array<std::uint32_t, 3> bits;
  std::memcpy(bits.data(), p.data(), sizeof bits);
  return (static_cast<std::size_t>(bits[0]) * 73856093u) ^ (static_cast<std::size_t>(bits[1]) * 19349663u) ^
         (static_cast<std::size_t>(bits[2]) * 83492791u);
}

int PositionWelder::operator()(int v) {
  // +0.0f folds -0.0f into 0.0f, whose bits differ.
  const std::array<float, 3> p{positions_(v, 0) + 0.0f, positions_(v, 1) + 0.0f, positions_(v, 2) + 0.0f};
  return first_.try_emplace(p, v).first->second;
}

std::vector<int> weld_by_position(const mesh::RowMatrixXf<3>& positions) {
  PositionWelder weld(positions);
  std::vector<int> out(static_cast<std::size_t>(positions.rows()));
  for (Eigen::Index i = 0; i < positions.rows(); ++i) out[static_cast<std::size_t>(i)] = weld(static_cast<int>(i));
  return out;
}

Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d axis = std::abs(n.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(axis).normalized();
}

void require_placement_fits(const anim::RiggedModel& model, const Placement& placement) {
  if (placement.positions.size() != model.meshes.size())
    throw InvalidInputError("surgery: the placement has " + std::to_string(placement.positions.size()) +
                            " meshes, the model " + std::to_string(model.meshes.size()));
  for (std::size_t i = 0; i < model.meshes.size(); ++i)
    if (placement.positions[i].rows() != model.meshes[i].vertex_count())
      throw InvalidInputError("surgery: mesh '" + model.meshes[i].name + "' has " +
                              std::to_string(model.meshes[i].vertex_count()) + " vertices but " +
                              std::to_string(placement.positions[i].rows()) + " placed positions");
}

}  // namespace cgamesh::surgery
