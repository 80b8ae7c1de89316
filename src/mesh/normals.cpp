#include "cgamesh/mesh/normals.hpp"

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/weld.hpp"

namespace cgamesh::mesh {

RowMatrixXf<3> area_weighted_normals(const RowMatrixXf<3>& positions, const Faces& faces) {
  RowMatrixXf<3> n = RowMatrixXf<3>::Zero(positions.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3f a = positions.row(faces(f, 0)), b = positions.row(faces(f, 1)),
                          c = positions.row(faces(f, 2));
    const Eigen::RowVector3f fn = (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) n.row(faces(f, k)) += fn;
  }
  for (Eigen::Index v = 0; v < n.rows(); ++v)
    if (n.row(v).norm() > 0) n.row(v).normalize();
  return n;
}

RowMatrixXf<3> reshaped_normals(const Mesh& m, const RowMatrixXf<3>& positions) {
  const Eigen::Index n = m.vertex_count();
  if (positions.rows() != n)
    throw InvalidInputError("reshaped_normals: " + std::to_string(positions.rows()) + " positions for a mesh of " +
                            std::to_string(n) + " vertices");
  if (m.normals.rows() != n) return RowMatrixXf<3>(0, 3);

  // Smoothing groups: per rest position, each copy joins the first group whose normal agrees
  // with its own, else starts one (copies at one position are few: seams, not the mesh).
  constexpr float same_direction = 0.99985f;  // cos 1°
  const std::vector<int> at = weld_by_position(m.positions);
  std::vector<int> group(static_cast<std::size_t>(n)), next_group_at(static_cast<std::size_t>(n), -1);
  for (Eigen::Index v = 0; v < n; ++v) {
    int* link = &next_group_at[static_cast<std::size_t>(at[static_cast<std::size_t>(v)])];
    int g = at[static_cast<std::size_t>(v)];
    while (g != v && m.normals.row(v).dot(m.normals.row(g)) < same_direction) {
      if (*link < 0) *link = static_cast<int>(v);
      g = *link;
      link = &next_group_at[static_cast<std::size_t>(g)];
    }
    group[static_cast<std::size_t>(v)] = g;
  }

  Eigen::MatrixX3d sum = Eigen::MatrixX3d::Zero(n, 3);
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3d a = positions.row(m.faces(f, 0)).cast<double>().transpose();
    const Eigen::Vector3d b = positions.row(m.faces(f, 1)).cast<double>().transpose();
    const Eigen::Vector3d c = positions.row(m.faces(f, 2)).cast<double>().transpose();
    const Eigen::RowVector3d area_normal = (b - a).cross(c - a).transpose();  // twice the area
    for (int k = 0; k < 3; ++k) sum.row(group[static_cast<std::size_t>(m.faces(f, k))]) += area_normal;
  }
  RowMatrixXf<3> out(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::RowVector3d s = sum.row(group[static_cast<std::size_t>(v)]);
    const double length = s.norm();
    if (length > 0)
      out.row(v) = (s / length).cast<float>();
    else
      out.row(v) = m.normals.row(v);
  }
  return out;
}

}  // namespace cgamesh::mesh
