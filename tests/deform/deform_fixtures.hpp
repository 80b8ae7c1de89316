#pragma once
// Meshes and vertex selections shared by the deformation tests.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/mesh.hpp"

#include "anim/model_fixtures.hpp"

namespace cgamesh_deform_test {

using cgamesh::mesh::Mesh;

/// An open cylinder of radius 1 along z in [0, 1]: `rings` rings of `around` vertices, each band
/// triangulated the same way. With `split_seam` the vertices at angle 0 are duplicated (as a
/// UV seam does), the last column of each ring at the position of the first.
inline Mesh cylinder(int around, int rings, bool split_seam = false) {
  const int columns = around + (split_seam ? 1 : 0);
  Mesh m;
  m.positions.resize(static_cast<Eigen::Index>(columns) * rings, 3);
  for (int r = 0; r < rings; ++r)
    for (int c = 0; c < columns; ++c) {
      const double a = 2.0 * std::numbers::pi * (c % around) / around;
      m.positions.row(r * columns + c) << static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)),
          static_cast<float>(static_cast<double>(r) / (rings - 1));
    }
  std::vector<int> f;
  for (int r = 0; r + 1 < rings; ++r)
    for (int c = 0; c < around; ++c) {
      const int c1 = split_seam ? c + 1 : (c + 1) % around;
      const int a = r * columns + c, b = r * columns + c1, d = (r + 1) * columns + c, e = (r + 1) * columns + c1;
      f.insert(f.end(), {a, b, e, a, e, d});
    }
  m.faces.resize(static_cast<Eigen::Index>(f.size() / 3), 3);
  std::copy(f.begin(), f.end(), m.faces.data());
  return m;
}

/// x ↦ K x for a versor K, on every row.
inline cgamesh::mesh::RowMatrixXf<3> moved(const cgamesh::mesh::RowMatrixXf<3>& p,
                                           const cgamesh::cga::Versor<double>& k) {
  const Eigen::Matrix<double, 3, 4> m = cgamesh::cga::PointMap<double>(k).affine_matrix();
  cgamesh::mesh::RowMatrixXf<3> out(p.rows(), 3);
  for (Eigen::Index i = 0; i < p.rows(); ++i)
    out.row(i) = (m.leftCols<3>() * p.row(i).transpose().cast<double>() + m.col(3)).transpose().cast<float>();
  return out;
}

/// The first mesh of a test asset.
inline Mesh asset_mesh(const std::string& name) {
  return cgamesh::io::load_model(cgamesh_test::asset(name)).meshes.at(0);
}

/// Vertices whose coordinate `axis` is within `fraction` of the extent from the minimum
/// (from_max false) or the maximum.
inline std::vector<int> slab(const Mesh& m, int axis, double fraction, bool from_max) {
  const float lo = m.positions.col(axis).minCoeff(), hi = m.positions.col(axis).maxCoeff();
  const double cut = from_max ? hi - fraction * (hi - lo) : lo + fraction * (hi - lo);
  std::vector<int> out;
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const double x = m.positions(i, axis);
    if (from_max ? x >= cut : x <= cut) out.push_back(static_cast<int>(i));
  }
  return out;
}

/// The `count` vertices nearest to `p`.
inline std::vector<int> nearest(const Mesh& m, const Eigen::Vector3f& p, int count) {
  std::vector<int> idx(static_cast<std::size_t>(m.vertex_count()));
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
  const auto d = [&](int i) { return (m.positions.row(i).transpose() - p).squaredNorm(); };
  std::partial_sort(idx.begin(), idx.begin() + count, idx.end(), [&](int a, int b) { return d(a) < d(b); });
  idx.resize(static_cast<std::size_t>(count));
  return idx;
}

inline double diagonal(const Mesh& m) {
  return (m.positions.colwise().maxCoeff() - m.positions.colwise().minCoeff()).cast<double>().norm();
}

/// `count` motors that differ per index: turns of up to ≈ 2.4 rad about varied axes, shifts, and
/// with `dilate` scales in [0.9, 1.1] (every third motor rigid).
inline std::vector<cgamesh::cga::Versor<double>> varied_motors(std::size_t count, bool dilate) {
  std::vector<cgamesh::cga::Versor<double>> out;
  for (std::size_t c = 0; c < count; ++c) {
    const double x = static_cast<double>(c);
    const auto rotor = cgamesh::cga::rotor(Eigen::Vector3d(std::sin(x), std::cos(2 * x), 1).normalized(),
                                           0.4 * static_cast<double>(c % 7));
    const double scale = dilate ? std::exp(0.1 * std::sin(3 * x) * static_cast<double>(c % 3 != 0)) : 1.0;
    out.push_back(cgamesh::cga::similarity(Eigen::Vector3d(0.1 * std::cos(x), 0.05 * x, -0.02), rotor, scale));
  }
  return out;
}

/// A motor frame one vertex at a time in double, p = exp(Σ w log R) p̂ (eqs. 7–8) from a
/// deformer's public weights(i): the reference of the frames' single-precision block kernel.
template <class Deformer>
cgamesh::mesh::RowMatrixXf<3> blended_reference(const Deformer& d, const cgamesh::mesh::RowMatrixXf<3>& rest,
                                                std::span<const cgamesh::cga::Versor<double>> motors) {
  const auto logs = cgamesh::deform::similarity_logs(motors);
  cgamesh::mesh::RowMatrixXf<3> out(rest.rows(), 3);
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    cgamesh::cga::SimilarityGenerator<double> b;
    for (const auto& [c, w] : d.weights(i)) b += logs[static_cast<std::size_t>(c)] * w;
    const Eigen::Matrix<double, 3, 4> m = cgamesh::deform::similarity_exp_affine(b);
    out.row(i) = (m.leftCols<3>() * rest.row(i).transpose().cast<double>() + m.col(3)).transpose().cast<float>();
  }
  return out;
}

}  // namespace cgamesh_deform_test
