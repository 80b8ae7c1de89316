#include "cgamesh/deform/morph_transport.hpp"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/weld.hpp"

namespace cgamesh::deform {

std::vector<Eigen::Matrix3d> local_linear_maps(const mesh::RowMatrixXf<3>& rest, const mesh::RowMatrixXf<3>& moved,
                                               const mesh::Faces& faces) {
  if (rest.rows() != moved.rows())
    throw InvalidInputError("local linear maps: " + std::to_string(moved.rows()) + " moved positions for " +
                            std::to_string(rest.rows()) + " vertices");
  std::vector<int> cls = mesh::weld_by_position(rest);
  const int count = mesh::number_classes(cls);
  // Per class: the normal equations A = Σ e eᵀ, B = Σ e′ eᵀ of the edges, the summed face
  // normals (area-weighted) and areas.
  struct Sums {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero(), b = Eigen::Matrix3d::Zero();
    Eigen::Vector3d n = Eigen::Vector3d::Zero(), n_moved = Eigen::Vector3d::Zero();
    double area = 0, area_moved = 0;
    int edges = 0;
  };
  std::vector<Sums> sums(static_cast<std::size_t>(count));
  const auto row = [](const mesh::RowMatrixXf<3>& p, int v) { return Eigen::Vector3d(p.row(v).cast<double>()); };
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const int i0 = faces(f, 0), i1 = faces(f, 1), i2 = faces(f, 2);
    const Eigen::Vector3d n = (row(rest, i1) - row(rest, i0)).cross(row(rest, i2) - row(rest, i0));
    const Eigen::Vector3d n_moved = (row(moved, i1) - row(moved, i0)).cross(row(moved, i2) - row(moved, i0));
    for (int k = 0; k < 3; ++k) {
      const int v = faces(f, k);
      Sums& s = sums[static_cast<std::size_t>(cls[static_cast<std::size_t>(v)])];
      s.n += n;
      s.n_moved += n_moved;
      s.area += n.norm();
      s.area_moved += n_moved.norm();
      for (const int w : {faces(f, (k + 1) % 3), faces(f, (k + 2) % 3)}) {
        const Eigen::Vector3d e = row(rest, w) - row(rest, v), e_moved = row(moved, w) - row(moved, v);
        s.a += e * e.transpose();
        s.b += e_moved * e.transpose();
        ++s.edges;
      }
    }
  }
  std::vector<Eigen::Matrix3d> per_class(static_cast<std::size_t>(count), Eigen::Matrix3d::Identity());
  for (std::size_t c = 0; c < sums.size(); ++c) {
    Sums& s = sums[c];
    if (s.edges == 0 || !(s.n.norm() > 0) || !(s.n_moved.norm() > 0)) continue;
    // The normal's length: the square root of the area around, a length that a similarity
    // scales as it scales edges, and that a deformation keeping area (a twist) keeps.
    const Eigen::Vector3d n = s.n.normalized() * std::sqrt(s.area),
                          n_moved = s.n_moved.normalized() * std::sqrt(s.area_moved);
    s.a += n * n.transpose();
    s.b += n_moved * n.transpose();
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(s.a);
    if (!lu.isInvertible()) continue;
    const Eigen::Matrix3d j = s.b * lu.inverse();
    if (j.allFinite()) per_class[c] = j;
  }
  std::vector<Eigen::Matrix3d> out(static_cast<std::size_t>(rest.rows()));
  for (std::size_t v = 0; v < out.size(); ++v) out[v] = per_class[static_cast<std::size_t>(cls[v])];
  return out;
}

void transport_morph_targets(mesh::Mesh& m, const mesh::RowMatrixXf<3>& moved) {
  if (m.morph_targets.empty()) return;
  if (moved.rows() != m.vertex_count())
    throw InvalidInputError("morph targets: " + std::to_string(moved.rows()) + " new positions for mesh '" + m.name +
                            "' of " + std::to_string(m.vertex_count()) + " vertices");
  const std::vector<Eigen::Matrix3d> maps = local_linear_maps(m.positions, moved, m.faces);
  std::vector<Eigen::Matrix3f> rotations(maps.size());
  for (std::size_t v = 0; v < maps.size(); ++v) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(maps[v], Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d u = svd.matrixU();
    if ((u * svd.matrixV().transpose()).determinant() < 0) u.col(2) = -u.col(2);
    rotations[v] = (u * svd.matrixV().transpose()).cast<float>();
  }
  for (mesh::MorphTarget& t : m.morph_targets) {
    for (Eigen::Index v = 0; v < t.positions.rows(); ++v)
      t.positions.row(v) = (maps[static_cast<std::size_t>(v)].cast<float>() * t.positions.row(v).transpose()).transpose();
    for (Eigen::Index v = 0; v < t.normals.rows(); ++v)
      t.normals.row(v) = (rotations[static_cast<std::size_t>(v)] * t.normals.row(v).transpose()).transpose();
  }
}

}  // namespace cgamesh::deform
